#include "dataset/euroc.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace slt {
namespace {

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("slt_euroc_" + std::to_string(::getpid()) + "_" + name)).string();
}

TEST(Euroc, SensorYamlInEurocsStyle) {
  EurocCameraInfo c;
  c.comment = "test camera";
  c.body_from_cam = Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.1, 0, 0));
  c.rate_hz = 30;
  c.width = 640;
  c.height = 480;
  c.intrinsics = {848.7, 848.7, 319.5, 239.5};
  const std::string path = TempPath("sensor.yaml");
  WriteEurocCameraYaml(path, c);
  EXPECT_EQ(ReadText(path),
            "%YAML:1.0\n"
            "# General sensor definitions.\n"
            "sensor_type: camera\n"
            "comment: test camera\n"
            "\n"
            "# Sensor extrinsics wrt. the body-frame.\n"
            "T_BS:\n"
            "  cols: 4\n"
            "  rows: 4\n"
            "  data: [1, 0, 0, 0.1,\n"
            "         0, 1, 0, 0,\n"
            "         0, 0, 1, 0,\n"
            "         0, 0, 0, 1]\n"
            "\n"
            "# Camera specific definitions.\n"
            "rate_hz: 30\n"
            "resolution: [640, 480]\n"
            "camera_model: pinhole\n"
            "intrinsics: [848.7, 848.7, 319.5, 239.5] #fu, fv, cu, cv\n"
            "distortion_model: radial-tangential\n"
            "distortion_coefficients: [0, 0, 0, 0]\n"
            "\n");
  std::filesystem::remove(path);
}

TEST(Euroc, GroundTruthHasEurocsColumns) {
  // Uniform motion along x at 0.3 m/s, turned 90 deg about z.
  Trajectory t;
  const Eigen::Matrix3d r = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (int k = 0; k < 3; ++k) t.push_back({0.1 * k, Rigid3d(r, Eigen::Vector3d(0.03 * k, 0, 0))});
  const std::string path = TempPath("gt.csv");
  WriteEurocGroundTruth(path, t);
  std::istringstream lines(ReadText(path));
  std::string header, row;
  std::getline(lines, header);
  EXPECT_EQ(header.rfind("#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x []", 0), 0u);
  std::getline(lines, row);
  std::getline(lines, row);  // the middle pose: t = 0.1 s
  std::vector<double> values;
  std::stringstream fields(row);
  for (std::string field; std::getline(fields, field, ',');) values.push_back(std::stod(field));
  ASSERT_EQ(values.size(), 17u);
  EXPECT_EQ(values[0], 100000000.0);
  EXPECT_NEAR(values[1], 0.03, 1e-15);
  EXPECT_NEAR(values[4], std::sqrt(0.5), 1e-12);  // q_w
  EXPECT_NEAR(values[7], std::sqrt(0.5), 1e-12);  // q_z
  EXPECT_NEAR(values[8], 0.3, 1e-12);             // v_x
  EXPECT_EQ(EurocTimestampNs(1.0 / 30.0), 33333333);
  std::filesystem::remove(path);
}

TEST(Euroc, CameraYamlReadsBackWhatWasWritten) {
  EurocCameraInfo c;
  c.comment = "right";
  c.body_from_cam = Rigid3d(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                            Eigen::Vector3d(0.11, -0.002, 0.003));
  c.rate_hz = 20;
  c.width = 752;
  c.height = 480;
  c.intrinsics = {458.654, 457.296, 367.215, 248.375};
  c.distortion = {-0.28, 0.07, 0.0002, 1.7e-05};
  const std::string path = TempPath("readback.yaml");
  WriteEurocCameraYaml(path, c);
  const EurocCameraInfo r = ReadEurocCameraYaml(path);
  EXPECT_EQ(r.comment, "right");
  EXPECT_TRUE(r.body_from_cam.rotation.isApprox(c.body_from_cam.rotation, 1e-12));
  EXPECT_TRUE(r.body_from_cam.translation.isApprox(c.body_from_cam.translation, 1e-12));
  EXPECT_EQ(r.rate_hz, 20);
  EXPECT_EQ(r.width, 752);
  EXPECT_EQ(r.height, 480);
  EXPECT_EQ(r.intrinsics.fx, 458.654);
  EXPECT_EQ(r.intrinsics.cy, 248.375);
  EXPECT_EQ(r.distortion[3], 1.7e-05);
  std::filesystem::remove(path);
}

TEST(Euroc, CameraYamlErrorsNameTheFileAndKey) {
  const std::string path = TempPath("bad.yaml");
  {
    std::ofstream out(path);
    out << "%YAML:1.0\nT_BS:\n  cols: 4\n  rows: 4\n  data: [1, 0, 0, 0,\n 0, 1, 0, 0,\n 0, 0, 1, 0,\n"
           " 0, 0, 0, 1]\nresolution: [752, 480]\nintrinsics: [458, 457, 367]\n";
  }
  try {
    ReadEurocCameraYaml(path);
    FAIL() << "three intrinsics accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'intrinsics'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadEurocCameraYaml(path + ".missing"), std::runtime_error);
  std::filesystem::remove(path);
}

TEST(Euroc, ImageListReadsBackAndRejectsDisorder) {
  const std::string path = TempPath("data.csv");
  WriteEurocImageList(path, {0, 33333333, 66666667});
  const std::vector<EurocImageEntry> entries = ReadEurocImageList(path);
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[1].timestamp_ns, 33333333);
  EXPECT_EQ(entries[2].filename, "66666667.png");
  {
    std::ofstream out(path);
    out << "#timestamp [ns],filename\n10,10.png\n5,5.png\n";
  }
  try {
    ReadEurocImageList(path);
    FAIL() << "decreasing timestamps accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace slt
