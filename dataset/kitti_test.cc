#include "dataset/kitti.h"

#include <gtest/gtest.h>
#include <unistd.h>

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
  return (std::filesystem::temp_directory_path() / ("slt_kitti_" + std::to_string(::getpid()) + "_" + name)).string();
}

StereoRig KittiRig() {
  StereoRig rig;
  rig.width = 1241;
  rig.height = 376;
  rig.left = rig.right = {718.856, 718.856, 607.1928, 185.2157};
  rig.right_from_left = Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-386.1448 / 718.856, 0.0, 0.0));
  return rig;
}

TEST(Kitti, CalibrationInKittisStyle) {
  const std::string path = TempPath("calib.txt");
  WriteKittiCalibration(path, KittiRig());
  // KITTI odometry's sequence 00, P0 and P1, to the digit.
  EXPECT_EQ(ReadText(path),
            "P0: 7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 0.000000000000e+00 0.000000000000e+00 "
            "7.188560000000e+02 1.852157000000e+02 0.000000000000e+00 0.000000000000e+00 0.000000000000e+00 "
            "1.000000000000e+00 0.000000000000e+00\n"
            "P1: 7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 -3.861448000000e+02 0.000000000000e+00 "
            "7.188560000000e+02 1.852157000000e+02 0.000000000000e+00 0.000000000000e+00 0.000000000000e+00 "
            "1.000000000000e+00 0.000000000000e+00\n");
  std::filesystem::remove(path);
}

TEST(Kitti, OnlyARectifiedPairCanBeWritten) {
  const std::string path = TempPath("refused.txt");
  StereoRig rig = KittiRig();
  rig.right.cx += 1.0;  // different intrinsics
  EXPECT_THROW(WriteKittiCalibration(path, rig), std::invalid_argument);
  rig = KittiRig();
  rig.right_from_left.translation.y() = 0.01;  // not along x
  EXPECT_THROW(WriteKittiCalibration(path, rig), std::invalid_argument);
  rig = KittiRig();
  rig.right_from_left.translation.x() = 0.5;  // the right camera on the left: swapped
  EXPECT_THROW(WriteKittiCalibration(path, rig), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(Kitti, TimesAndImageNames) {
  const std::string path = TempPath("times.txt");
  WriteKittiTimes(path, {0.0, 0.1, 12.5});
  EXPECT_EQ(ReadText(path), "0.000000000000e+00\n1.000000000000e-01\n1.250000000000e+01\n");
  std::filesystem::remove(path);
  EXPECT_EQ(KittiImageName(0), "000000.png");
  EXPECT_EQ(KittiImageName(4540), "004540.png");
  EXPECT_EQ(KittiImageName(1234567), "1234567.png");
}

}  // namespace
}  // namespace slt
