#include "frontend/image_sequence.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <opencv2/imgcodecs.hpp>

#include "common/json_changes.h"
#include "dataset/euroc.h"
#include "geometry/distortion.h"
#include "render/sequence_renderer.h"

namespace slt {
namespace {
namespace fs = std::filesystem;

// A fresh folder per test and process.
fs::path TempFolder(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("image_sequence_test_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void WriteText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

// A grey image whose pixels encode the frame and the camera.
cv::Mat Pattern(int frame, int camera, int width = 24, int height = 16) {
  cv::Mat image(height, width, CV_8UC1);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) image.at<unsigned char>(v, u) = static_cast<unsigned char>(10 * frame + 100 * camera + u);
  }
  return image;
}

// fx = 700, cx = 12, cy = 8, baseline 0.5 m.
const char* kKittiCalib =
    "P0: 700 0 12 0 0 700 8 0 0 0 1 0\n"
    "P1: 700 0 12 -350 0 700 8 0 0 0 1 0\n"
    "P2: 700 0 12 40 0 700 8 0.2 0 0 1 0.003\n";

fs::path KittiFolder(const std::string& name, int frames, const std::string& left = "image_0",
                     const std::string& right = "image_1") {
  const fs::path dir = TempFolder(name);
  fs::create_directories(dir / left);
  fs::create_directories(dir / right);
  for (int k = 0; k < frames; ++k) {
    char file[16];
    std::snprintf(file, sizeof(file), "%06d.png", k);
    cv::imwrite((dir / left / file).string(), Pattern(k, 0));
    cv::imwrite((dir / right / file).string(), Pattern(k, 1));
  }
  WriteText(dir / "calib.txt", kKittiCalib);
  return dir;
}

TEST(KittiLayout, ReadsRigTimesImagesAndGroundTruth) {
  const fs::path dir = KittiFolder("kitti_ok", 3);
  WriteText(dir / "poses.txt",
            "1 0 0 0 0 1 0 0 0 0 1 0\n"
            "1 0 0 0.1 0 1 0 0 0 0 1 1\n"
            "1 0 0 0.2 0 1 0 0 0 0 1 2\n");
  ASSERT_EQ(DetectDatasetLayout(dir.string()), DatasetLayout::kKitti);
  const auto source = OpenStereoImages(dir.string());
  ASSERT_EQ(source->size(), 3);
  EXPECT_EQ(source->rig().width, 24);
  EXPECT_EQ(source->rig().height, 16);
  EXPECT_DOUBLE_EQ(source->rig().left.fx, 700.0);
  EXPECT_DOUBLE_EQ(source->rig().left.cx, 12.0);
  // P1(0, 3) = -fx * baseline: the right camera's centre at x = +0.5 m, t = (-0.5, 0, 0).
  EXPECT_TRUE(source->rig().right_from_left.translation.isApprox(Eigen::Vector3d(-0.5, 0, 0)));
  // No times.txt: KITTI's 10 Hz.
  EXPECT_DOUBLE_EQ(source->Time(2), 0.2);
  const StereoImages images = source->Read(1);
  EXPECT_EQ(cv::norm(images.left, Pattern(1, 0), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(images.right, Pattern(1, 1), cv::NORM_INF), 0.0);
  ASSERT_EQ(source->ground_truth().size(), 3u);
  EXPECT_DOUBLE_EQ(source->ground_truth()[2].time, 0.2);
  EXPECT_TRUE(source->ground_truth()[2].world_from_cam.translation.isApprox(Eigen::Vector3d(0.2, 0, 2)));

  WriteText(dir / "times.txt", "0\n0.05\n0.125\n");
  EXPECT_DOUBLE_EQ(OpenStereoImages(dir.string())->Time(2), 0.125);
  EXPECT_DOUBLE_EQ(OpenStereoImages(dir.string())->ground_truth()[2].time, 0.125);
}

TEST(KittiLayout, AlsoReadsImageLAndImageRAndUnkeyedCalibration) {
  const fs::path dir = KittiFolder("kitti_lr", 2, "image_l", "image_r");
  // Two lines of 12 numbers without "P0:" / "P1:" (as the shared excerpt has them).
  WriteText(dir / "calib.txt", "700 0 12 0 0 700 8 0 0 0 1 0\n700 0 12 -350 0 700 8 0 0 0 1 0\n");
  ASSERT_EQ(DetectDatasetLayout(dir.string()), DatasetLayout::kKitti);
  const auto source = OpenStereoImages(dir.string(), DatasetLayout::kKitti);
  ASSERT_EQ(source->size(), 2);
  EXPECT_EQ(cv::norm(source->Read(1).right, Pattern(1, 1), cv::NORM_INF), 0.0);
  EXPECT_TRUE(source->rig().right_from_left.translation.isApprox(Eigen::Vector3d(-0.5, 0, 0)));
  EXPECT_TRUE(source->ground_truth().empty());
}

TEST(KittiLayout, ErrorsNameTheFile) {
  {
    const fs::path dir = KittiFolder("kitti_gap", 3);
    fs::remove(dir / "image_0" / "000001.png");
    const std::string error = ErrorOf([&] { OpenStereoImages(dir.string()); });
    EXPECT_NE(error.find((dir / "image_0" / "000001.png").string() + ": image missing"), std::string::npos) << error;
  }
  {
    const fs::path dir = KittiFolder("kitti_count", 3);
    fs::remove(dir / "image_1" / "000002.png");
    const std::string error = ErrorOf([&] { OpenStereoImages(dir.string()); });
    EXPECT_NE(error.find((dir / "image_1").string() + ": 2 images, but"), std::string::npos) << error;
  }
  {
    const fs::path dir = KittiFolder("kitti_png", 3);
    WriteText(dir / "image_1" / "000002.png", "not a png");
    const auto source = OpenStereoImages(dir.string());
    const std::string error = ErrorOf([&] { source->Read(2); });
    EXPECT_NE(error.find((dir / "image_1" / "000002.png").string() + ": cannot read the image"), std::string::npos)
        << error;
  }
  {
    const fs::path dir = KittiFolder("kitti_size", 2);
    cv::imwrite((dir / "image_1" / "000001.png").string(), Pattern(1, 1, 20, 16));
    const std::string error = ErrorOf([&] { OpenStereoImages(dir.string())->Read(1); });
    EXPECT_NE(error.find("000001.png: image is 20 x 16, the calibration says 24 x 16"), std::string::npos) << error;
  }
  {
    const fs::path dir = KittiFolder("kitti_calib", 2);
    const std::string calib = (dir / "calib.txt").string();
    WriteText(calib, "P0: 700 0 12 0 0 700 8 0 0 0 1 0\n");
    EXPECT_EQ(ErrorOf([&] { OpenStereoImages(dir.string()); }), calib + ": missing key 'P1:' (nor two lines of 12 numbers, P0 and P1)");
    WriteText(calib, "700 0 12 0 0 700 8 0 0 0 1 0\n");
    EXPECT_EQ(ErrorOf([&] { OpenStereoImages(dir.string()); }),
              calib + ": missing key 'P0:' (nor two lines of 12 numbers, P0 and P1)");
    WriteText(calib, "P0: 700 0 12 0 0 700 8 0 0 0 1 0\nP1: 700 0 12 -350 0 700 8 0 0 0 1\n");
    EXPECT_EQ(ErrorOf([&] { OpenStereoImages(dir.string()); }), calib + ": key 'P1': expected 12 numbers");
    WriteText(calib, "P0: 700 0 12 0 0 700 8 0 0 0 1 0\nP1: 700 0 12 0 0 700 8 0 0 0 1 0\n");
    EXPECT_NE(ErrorOf([&] { OpenStereoImages(dir.string()); }).find(calib + ": unusable stereo rig"), std::string::npos);
    fs::remove(calib);
    EXPECT_THROW(OpenStereoImages(dir.string(), DatasetLayout::kKitti), std::runtime_error);
    EXPECT_EQ(ErrorOf([&] { OpenStereoImages(dir.string(), DatasetLayout::kKitti); }), calib + ": calibration missing");
  }
  {
    const fs::path dir = KittiFolder("kitti_times", 3);
    const std::string times = (dir / "times.txt").string();
    WriteText(times, "0\n0.2\n0.1\n");
    EXPECT_EQ(ErrorOf([&] { OpenStereoImages(dir.string()); }), times + ": line 3: times must increase");
    WriteText(times, "0\n0.1\n");
    EXPECT_EQ(ErrorOf([&] { OpenStereoImages(dir.string()); }), times + ": 2 times for 3 stereo pairs");
    WriteText(times, "0\n0.1\nx\n");
    EXPECT_EQ(ErrorOf([&] { OpenStereoImages(dir.string()); }), times + ": line 3: not a number: 'x'");
  }
  {
    const fs::path dir = KittiFolder("kitti_poses", 3);
    const std::string poses = (dir / "poses.txt").string();
    WriteText(poses, "1 0 0 0 0 1 0 0 0 0 1 0\n");
    EXPECT_EQ(ErrorOf([&] { OpenStereoImages(dir.string()); }), poses + ": 1 poses for 3 stereo pairs");
  }
}

// An ASL folder as EuRoC writes it; cam1 lists one image more than cam0 (skipped).
fs::path AslFolder(const std::string& name, const RadialTangential& distortion = {}) {
  const fs::path dir = TempFolder(name);
  const fs::path mav0 = dir / "mav0";
  for (int c = 0; c < 2; ++c) {
    const fs::path cam = mav0 / ("cam" + std::to_string(c));
    fs::create_directories(cam / "data");
    EurocCameraInfo info;
    info.width = 24;
    info.height = 16;
    info.intrinsics = {30.0, 30.0, 11.5, 7.5};
    info.distortion = distortion;
    // The body is rotated from the cameras (EuRoC's T_BS): x_body = -y_cam, y_body = x_cam.
    Eigen::Matrix3d body_from_cam;
    body_from_cam << 0, -1, 0, 1, 0, 0, 0, 0, 1;
    info.body_from_cam = Rigid3d(body_from_cam, body_from_cam * Eigen::Vector3d(0.1 * c, 0, 0));
    WriteEurocCameraYaml((cam / "sensor.yaml").string(), info);
    std::vector<std::int64_t> stamps = {1000000000, 1050000000, 1100000000};
    if (c == 1) stamps.push_back(1150000000);
    WriteEurocImageList((cam / "data.csv").string(), stamps);
    for (size_t k = 0; k < 3; ++k) {
      cv::imwrite((cam / "data" / (std::to_string(stamps[k]) + ".png")).string(), Pattern(static_cast<int>(k), c));
    }
  }
  return dir;
}

TEST(AslLayout, PairsByTimestampAndConvertsTheGroundTruthToTheLeftCamera) {
  const fs::path dir = AslFolder("asl_ok");
  Trajectory world_from_body = {{1.0, Rigid3d()}, {1.1, Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 0, 0))}};
  fs::create_directories(dir / "mav0" / "state_groundtruth_estimate0");
  WriteEurocGroundTruth((dir / "mav0" / "state_groundtruth_estimate0" / "data.csv").string(), world_from_body);
  ASSERT_EQ(DetectDatasetLayout(dir.string()), DatasetLayout::kAsl);
  const auto source = OpenStereoImages(dir.string());
  ASSERT_EQ(source->size(), 3);  // cam1's fourth image has no partner
  EXPECT_NE(source->Describe().find("1 images without a partner skipped"), std::string::npos) << source->Describe();
  // An ideal rig: the images pass through unchanged.
  EXPECT_EQ(source->Describe().find("rectified"), std::string::npos);
  EXPECT_EQ(cv::norm(source->Read(2).left, Pattern(2, 0), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(source->Read(2).right, Pattern(2, 1), cv::NORM_INF), 0.0);
  EXPECT_DOUBLE_EQ(source->Time(1), 1.05);
  EXPECT_TRUE(source->rig().right_from_left.translation.isApprox(Eigen::Vector3d(-0.1, 0, 0)));
  // The body moved 1 m along its x = the camera's -y.
  ASSERT_EQ(source->ground_truth().size(), 2u);
  const Trajectory gt = GroundTruthFromStart(source->ground_truth(), 1.0);
  EXPECT_TRUE(gt[0].world_from_cam.translation.isZero(1e-12));
  EXPECT_TRUE(gt[0].world_from_cam.rotation.isIdentity(1e-12));
  EXPECT_TRUE(gt[1].world_from_cam.translation.isApprox(Eigen::Vector3d(0, -1, 0), 1e-12))
      << gt[1].world_from_cam.translation.transpose();
  EXPECT_EQ(source->ground_truth_file(), (dir / "mav0" / "state_groundtruth_estimate0" / "data.csv").string());

  // A TUM ground truth given explicitly.
  WriteTumTrajectory((dir / "body.tum").string(), world_from_body);
  EXPECT_EQ(OpenStereoImages(dir.string(), DatasetLayout::kAsl, (dir / "body.tum").string())->ground_truth().size(), 2u);
  EXPECT_NE(ErrorOf([&] { OpenStereoImages(dir.string(), DatasetLayout::kAsl, (dir / "none.tum").string()); })
                .find("none.tum: ground truth file missing"),
            std::string::npos);
}

TEST(AslLayout, ErrorsNameTheFile) {
  {
    const fs::path dir = AslFolder("asl_missing");
    fs::remove(dir / "mav0" / "cam1" / "data" / "1050000000.png");
    EXPECT_NE(ErrorOf([&] { OpenStereoImages(dir.string()); })
                  .find((dir / "mav0" / "cam1" / "data" / "1050000000.png").string() + ": image missing"),
              std::string::npos);
  }
  {
    const fs::path dir = AslFolder("asl_order");
    const std::string csv = (dir / "mav0" / "cam0" / "data.csv").string();
    WriteText(csv, "#timestamp [ns],filename\n1050000000,1050000000.png\n1000000000,1000000000.png\n");
    EXPECT_EQ(ErrorOf([&] { OpenStereoImages(dir.string()); }), csv + ": line 3: timestamps must increase");
  }
  {
    const fs::path dir = AslFolder("asl_nothing_common");
    const std::string csv = (dir / "mav0" / "cam1" / "data.csv").string();
    WriteText(csv, "#timestamp [ns],filename\n7,7.png\n");
    EXPECT_NE(ErrorOf([&] { OpenStereoImages(dir.string()); }).find(csv + ": no timestamp in common"), std::string::npos);
  }
  {
    const fs::path dir = AslFolder("asl_png");
    WriteText(dir / "mav0" / "cam0" / "data" / "1100000000.png", "garbage");
    const auto source = OpenStereoImages(dir.string());
    EXPECT_NE(ErrorOf([&] { source->Read(2); }).find("1100000000.png: cannot read the image"), std::string::npos);
  }
  {
    const fs::path dir = AslFolder("asl_yaml");
    const std::string yaml = (dir / "mav0" / "cam1" / "sensor.yaml").string();
    std::ifstream in(yaml);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    text.replace(text.find("intrinsics: ["), 13, "intrinsics: [x, ");
    WriteText(yaml, text);
    const std::string error = ErrorOf([&] { OpenStereoImages(dir.string()); });
    EXPECT_NE(error.find(yaml + ": key 'intrinsics'"), std::string::npos) << error;
    fs::remove(yaml);
    EXPECT_NE(ErrorOf([&] { OpenStereoImages(dir.string()); }).find(yaml + ": cannot read"), std::string::npos);
  }
  {
    const fs::path dir = AslFolder("asl_gt");
    const std::string csv = (dir / "mav0" / "state_groundtruth_estimate0" / "data.csv").string();
    WriteText(csv, "#t,x,y,z,qw,qx,qy,qz\n1000000000,0,0,0,1,0,0,0\n1100000000,0,0,0,1,0\n");
    EXPECT_EQ(ErrorOf([&] { OpenStereoImages(dir.string()); }),
              csv + ": line 3: expected timestamp, p_RS_R (3) and q_RS (w x y z), got 6 columns");
  }
  EXPECT_NE(ErrorOf([&] { OpenStereoImages(TempFolder("empty").string()); }).find("neither the ASL/EuRoC layout"),
            std::string::npos);
}

TEST(AslLayout, DistortedPairsAreRectified) {
  const fs::path dir = AslFolder("asl_distorted", {-0.2, 0.05, 0.001, 0.0});
  const auto source = OpenStereoImages(dir.string());
  EXPECT_NE(source->Describe().find("undistorted and rectified"), std::string::npos);
  const StereoRig& rig = source->rig();
  // Rectified: identity rotation, baseline along x, the same fy and cy.
  EXPECT_TRUE(rig.right_from_left.rotation.isIdentity(1e-12));
  EXPECT_NEAR(rig.right_from_left.translation.x(), -0.1, 1e-9);
  EXPECT_EQ(rig.left.cy, rig.right.cy);
  EXPECT_EQ(source->Read(0).left.size(), cv::Size(24, 16));
}

TEST(KittiLayout, ReadsARenderedStreetAsItWasWritten) {
  // A rendered street in KITTI's layout reads back with the rig, times, images and ground truth
  // it was made with (WriteKittiSequence), as a downloaded KITTI sequence does.
  SimulationConfig config =
      SimulationConfigFromJson({{"scene", {{"type", "street"}}}, {"frames", 4}, {"motion", {{"profile", "car"}}}}, "t");
  config.rig.width = 320;  // the middle of KITTI's rig: a faster test
  config.rig.height = 96;
  for (PinholeCamera* camera : {&config.rig.left, &config.rig.right}) {
    camera->cx = 160.25;
    camera->cy = 48.5;
  }
  const SimulatedSequence sequence = Simulate(config);
  const fs::path dir = TempFolder("rendered_street");
  WriteKittiSequence(dir.string(), sequence, config, 2);
  const auto source = OpenStereoImages(dir.string());
  EXPECT_NE(source->Describe().find("KITTI"), std::string::npos) << source->Describe();
  ASSERT_EQ(source->size(), 4);
  const StereoRig& rig = source->rig();
  EXPECT_EQ(rig.width, 320);
  EXPECT_NEAR(rig.left.fx, 718.856, 1e-9);
  EXPECT_NEAR(rig.left.cx, 160.25, 1e-9);
  EXPECT_NEAR(rig.right_from_left.translation.x(), -386.1448 / 718.856, 1e-12);
  EXPECT_NEAR(source->Time(3), 0.3, 1e-12);
  const SequenceRenderer renderer(sequence, config);
  EXPECT_EQ(cv::norm(source->Read(2).right, renderer.Image(2, 1), cv::NORM_INF), 0.0);
  ASSERT_EQ(source->ground_truth().size(), 4u);
  for (int k = 0; k < 4; ++k) {
    const Eigen::Matrix4d error =
        source->ground_truth()[k].world_from_cam.ToMatrix4() - sequence.ground_truth[k].world_from_cam.ToMatrix4();
    EXPECT_LT(error.cwiseAbs().maxCoeff(), 1e-5) << k;  // poses.txt's 7 significant digits
  }
  // Lens distortion has no place in KITTI's layout: refused before anything is written.
  config.images.distortion = {-0.1, 0.0, 0.0, 0.0};
  const fs::path other = TempFolder("rendered_street_distorted");
  EXPECT_THROW(WriteKittiSequence(other.string(), sequence, config, 1), std::invalid_argument);
  EXPECT_TRUE(fs::is_empty(other));
}

// The real excerpts (../shared/data, README there), or the folder named by SLT_SHARED_DATA.
std::string SharedData() {
  const char* env = std::getenv("SLT_SHARED_DATA");
  return env != nullptr ? env : SLT_SHARED_DATA_DIR;
}

TEST(RealExcerpts, KittiExcerpt) {
  const std::string dir = SharedData() + "/kitti_excerpt_1";
  if (!fs::exists(dir)) GTEST_SKIP() << dir << " absent (the real excerpts are not part of the repository)";
  const auto source = OpenStereoImages(dir);
  ASSERT_EQ(source->size(), 51);
  // 1226 x 370 and fx = 707.09 (the calibration of KITTI odometry sequences 04-10; the data
  // README's 1241 x 376 and 718.856 are sequences 00-02's).
  EXPECT_EQ(source->rig().width, 1226);
  EXPECT_EQ(source->rig().height, 370);
  EXPECT_NEAR(source->rig().left.fx, 707.0912, 1e-9);
  EXPECT_NEAR(source->rig().Baseline(), 0.537, 0.001);
  ASSERT_EQ(source->ground_truth().size(), 51u);
  // About 1 m per frame.
  const double path = (source->ground_truth().back().world_from_cam.translation -
                       source->ground_truth().front().world_from_cam.translation).norm();
  EXPECT_GT(path, 30.0);
  EXPECT_EQ(source->Read(50).left.type(), CV_8UC1);
}

TEST(RealExcerpts, EurocExcerpt) {
  const std::string dir = SharedData() + "/euroc_v1_01_excerpt";
  if (!fs::exists(dir)) GTEST_SKIP() << dir << " absent (the real excerpts are not part of the repository)";
  const auto source = OpenStereoImages(dir);
  ASSERT_EQ(source->size(), 95);
  EXPECT_NE(source->Describe().find("undistorted and rectified"), std::string::npos);
  EXPECT_NEAR(source->rig().Baseline(), 0.110, 0.001);  // EuRoC's VI-sensor
  ASSERT_FALSE(source->ground_truth().empty());
  EXPECT_EQ(source->ground_truth_file(), dir + "/groundtruth_body.tum");
  // At rest: the body moves less than 3 mm (README); the camera, 7 cm from it, a little more.
  const Trajectory gt = GroundTruthFromStart(source->ground_truth(), source->Time(0));
  double largest = 0.0;
  for (const TimedPose& pose : gt) largest = std::max(largest, pose.world_from_cam.translation.norm());
  EXPECT_LT(largest, 0.005);
  EXPECT_GT(largest, 0.0);
}

}  // namespace
}  // namespace slt
