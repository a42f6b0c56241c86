#include "render/sequence_renderer.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "render/image_formation.h"

namespace slt {
namespace {

namespace fs = std::filesystem;

std::string ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Expects every file under `a` to have the same bytes as its namesake under `b`; returns how
// many there are.
std::size_t CompareFiles(const fs::path& a, const fs::path& b) {
  std::size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(a)) {
    if (!entry.is_regular_file()) continue;
    const fs::path relative = fs::relative(entry.path(), a);
    EXPECT_EQ(ReadBytes(entry.path()), ReadBytes(b / relative)) << relative;
    ++files;
  }
  return files;
}

// A small rig (160 x 120) keeps the sequences fast.
SimulationConfig SmallRoom(int frames) {
  nlohmann::json rig = {{"width", 160},
                        {"height", 120},
                        {"left", {{"fx", 212.0}, {"fy", 212.0}, {"cx", 79.5}, {"cy", 59.5}}},
                        {"right", {{"fx", 212.0}, {"fy", 212.0}, {"cx", 79.5}, {"cy", 59.5}}},
                        {"right_from_left", {{"R", {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}, {"t", {-0.1, 0, 0}}}}};
  return SimulationConfigFromJson(
      {{"scene", {{"type", "room"}}}, {"frames", frames}, {"rig", rig}, {"images", {{"motion_blur_samples", 2}}}},
      "test");
}

TEST(SequenceRenderer, EurocOutputIsIdenticalForAnyThreadCount) {
  const SimulationConfig config = SmallRoom(5);
  const SimulatedSequence sequence = Simulate(config);
  const fs::path base = fs::temp_directory_path() / ("slt_render_test_" + std::to_string(::getpid()));
  fs::remove_all(base);
  WriteEurocSequence((base / "one").string(), sequence, config, 1);
  WriteEurocSequence((base / "three").string(), sequence, config, 3);
  // 2 x 5 images, 2 x (data.csv, sensor.yaml), the ground truth.
  EXPECT_EQ(CompareFiles(base / "one", base / "three"), 15u);
  EXPECT_FALSE(fs::exists(base / "one" / "mav0.partial"));

  // The layout: EuRoC's image list and names, 8-bit grey PNGs of the rig's size.
  std::ifstream list(base / "one" / "mav0" / "cam1" / "data.csv");
  std::string header, first, second;
  std::getline(list, header);
  std::getline(list, first);
  std::getline(list, second);
  EXPECT_EQ(header, "#timestamp [ns],filename");
  EXPECT_EQ(first, "0,0.png");
  EXPECT_EQ(second, "33333333,33333333.png");
  const cv::Mat image = cv::imread((base / "one" / "mav0" / "cam1" / "data" / "33333333.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(image.type(), CV_8UC1);
  EXPECT_EQ(image.cols, 160);
  EXPECT_EQ(image.rows, 120);
  // And the same image as rendering it directly.
  const SequenceRenderer renderer(sequence, config);
  EXPECT_EQ(cv::norm(image, renderer.Image(1, 1), cv::NORM_INF), 0.0);
  fs::remove_all(base);
}

TEST(SequenceRenderer, KittiOutputIsIdenticalForAnyThreadCount) {
  const SimulationConfig config = SmallRoom(4);
  const SimulatedSequence sequence = Simulate(config);
  const fs::path base = fs::temp_directory_path() / ("slt_render_test_kitti_" + std::to_string(::getpid()));
  fs::remove_all(base);
  WriteKittiSequence((base / "one").string(), sequence, config, 1);
  WriteKittiSequence((base / "three").string(), sequence, config, 3);
  // 2 x 4 images, calib.txt, times.txt, poses.txt; no staging folder left.
  EXPECT_EQ(CompareFiles(base / "one", base / "three"), 11u);
  EXPECT_TRUE(fs::exists(base / "one" / "image_1" / "000003.png"));
  EXPECT_FALSE(fs::exists(base / "one" / "image_0.partial"));
  fs::remove_all(base);
}

TEST(SequenceRenderer, AutoExposureStepsAreBoundedRampedAndSharedByBothCameras) {
  ImageConfig images;
  EXPECT_EQ(AutoExposureGain(images, 1, 50), 1.0);  // off by default
  images.auto_exposure_step = 0.2;
  int steps = 0;
  double previous = AutoExposureGain(images, 1, 0);
  for (int k = 1; k < 600; ++k) {
    const double gain = AutoExposureGain(images, 1, k);
    EXPECT_GE(gain, 0.6 - 1e-12);
    EXPECT_LE(gain, 1.4 + 1e-12);
    // A step of at most 20 % is spread over the 3-frame ramp.
    EXPECT_LE(std::abs(gain / previous - 1.0), 0.2 / 3.0 + 0.02) << k;
    steps += gain != previous;
    previous = gain;
  }
  // About one step every 15 frames, each over 3 frames.
  EXPECT_GT(steps, 60);
  EXPECT_LT(steps, 180);
  EXPECT_NE(AutoExposureGain(images, 2, 300), AutoExposureGain(images, 1, 300));
  // Frame k's gain is the same whichever frames were asked for before.
  EXPECT_EQ(AutoExposureGain(images, 1, 300), AutoExposureGain(images, 1, 300));
  SimulationConfig config = SmallRoom(40);
  config.images.auto_exposure_step = 0.2;
  config.images.read_noise = 0.0;
  config.images.shot_noise = 0.0;
  config.images.exposure_variation = 0.0;
  const SimulatedSequence sequence = Simulate(config);
  const SequenceRenderer renderer(sequence, config);
  // The images' brightness follows the gain, left and right alike.
  for (const int k : {10, 30}) {
    const double ratio = cv::mean(renderer.Image(k, 0))[0] / cv::mean(renderer.Image(k, 1))[0];
    EXPECT_NEAR(ratio, 1.0, 0.05) << k;
  }
  const double gain_ratio = AutoExposureGain(config.images, config.ImageSeed(), 30) /
                            AutoExposureGain(config.images, config.ImageSeed(), 0);
  EXPECT_NEAR(cv::mean(renderer.Image(30, 0))[0] / cv::mean(renderer.Image(0, 0))[0], gain_ratio, 0.1);
}

TEST(SequenceRenderer, NoiseHasTheConfiguredSpread) {
  SimulationConfig config = SmallRoom(2);
  config.images.motion_blur_samples = 1;
  config.images.defocus_blur_px = 0.0;
  const SimulatedSequence sequence = Simulate(config);
  const SequenceRenderer renderer(sequence, config);
  const cv::Mat radiance = renderer.Radiance(0, 0);
  ImageConfig clean = config.images;
  clean.read_noise = clean.shot_noise = 0.0;
  const double gain = ExposureGain(config.images, config.ImageSeed(), 0);
  cv::Mat a, b;
  FormImage(radiance, clean, gain, 1).convertTo(a, CV_64F);
  FormImage(radiance, config.images, gain, 1).convertTo(b, CV_64F);
  // Expected variance: read^2 + shot * level, plus 1/12 from the rounding.
  double expected = 0.0, measured = 0.0;
  for (int y = 0; y < a.rows; ++y) {
    for (int x = 0; x < a.cols; ++x) {
      const double level = a.at<double>(y, x);
      if (level < 10 || level > 245) continue;
      expected += config.images.read_noise * config.images.read_noise + config.images.shot_noise * level + 1.0 / 12.0;
      measured += (b.at<double>(y, x) - level) * (b.at<double>(y, x) - level);
    }
  }
  EXPECT_NEAR(measured / expected, 1.0, 0.1);
  // A different key, different noise; the same key, the same image.
  EXPECT_GT(cv::norm(FormImage(radiance, config.images, gain, 1), FormImage(radiance, config.images, gain, 2),
                     cv::NORM_INF),
            0.0);
  EXPECT_EQ(cv::norm(FormImage(radiance, config.images, gain, 1), FormImage(radiance, config.images, gain, 1),
                     cv::NORM_INF),
            0.0);
}

TEST(SequenceRenderer, InterpolatedPosesMeetTheGroundTruth) {
  const SimulationConfig config = SmallRoom(100);
  const SimulatedSequence sequence = Simulate(config);
  const SequenceRenderer renderer(sequence, config);
  for (int k = 0; k < 4; ++k) {
    const Rigid3d expected = sequence.ground_truth[k].world_from_cam.Inverse();
    const Rigid3d got = renderer.CamFromWorld(k, 0);
    EXPECT_LT((got.rotation - expected.rotation).norm() + (got.translation - expected.translation).norm(), 1e-12);
  }
  // Halfway, the centre is between the neighbours' (to first order).
  const Eigen::Vector3d mid = renderer.CamFromWorld(1.5, 0).Center();
  const Eigen::Vector3d expected = 0.5 * (sequence.ground_truth[1].world_from_cam.translation +
                                          sequence.ground_truth[2].world_from_cam.translation);
  EXPECT_LT((mid - expected).norm(), 1e-4);
}

}  // namespace
}  // namespace slt
