#include "dataset/trajectory.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <unistd.h>

#include "common/csv.h"
#include "common/json_changes.h"
#include "common/json_reader.h"
#include "geometry/se3.h"

namespace slt {
namespace {

const std::string kTestData = std::string(SLT_SOURCE_DIR) + "/dataset/testdata/";

// Unique per process: ctest runs each test in its own process, possibly in parallel, and
// other build trees may run the same tests at the same time.
std::string TempPath(const std::string& name) {
  return ::testing::TempDir() + "trajectory_test_" + std::to_string(::getpid()) + "_" + name;
}

std::string ReadErrorOf(const std::string& contents, bool kitti = false) {
  const std::string path = TempPath("malformed.txt");
  WriteTextFileAtomically(path, contents);
  const std::string error = ErrorOf([&] { kitti ? ReadKittiTrajectory(path) : ReadTumTrajectory(path); });
  std::remove(path.c_str());
  EXPECT_EQ(error.rfind(path + ":", 0), 0u) << "error does not start with the file: " << error;
  return error.empty() ? error : error.substr(path.size());
}

Trajectory RandomTrajectory(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Trajectory trajectory;
  for (int k = 0; k < n; ++k) {
    const Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
    trajectory.push_back({1.0e9 + 0.033 * k + 1e-7 * normal(rng),
                          Rigid3d::FromQuaternion(q, Eigen::Vector3d(normal(rng), normal(rng), 1e-5 * normal(rng)))});
  }
  return trajectory;
}

void ExpectSamePoses(const Trajectory& a, const Trajectory& b, bool same_times) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    if (same_times) {
      EXPECT_EQ(a[k].time, b[k].time);
    }
    EXPECT_EQ(a[k].world_from_cam.translation, b[k].world_from_cam.translation) << "pose " << k;
    EXPECT_TRUE(a[k].world_from_cam.rotation.isApprox(b[k].world_from_cam.rotation, 1e-15)) << "pose " << k;
  }
}

TEST(Trajectory, TumRoundTripIsExact) {
  const Trajectory written = RandomTrajectory(200, 1);
  const std::string path = TempPath("round_trip.tum");
  WriteTumTrajectory(path, written);
  ExpectSamePoses(ReadTumTrajectory(path), written, true);
  std::remove(path.c_str());
}

// Pose by pose, the same file as WriteTumTrajectory, in place only after Close(); abandoned (an
// error in the producer), no file at all.
TEST(Trajectory, TumWriterStreamsTheSameFileOrNone) {
  const Trajectory written = RandomTrajectory(50, 2);
  const std::string whole = TempPath("whole.tum"), streamed = TempPath("streamed.tum");
  WriteTumTrajectory(whole, written);
  {
    TumTrajectoryWriter writer(streamed);
    for (const TimedPose& pose : written) writer.Append(pose);
    EXPECT_FALSE(std::ifstream(streamed).good()) << "visible before Close()";
    writer.Close();
  }
  EXPECT_EQ(ReadTextFile(whole), ReadTextFile(streamed));
  const std::string abandoned = TempPath("abandoned.tum");
  {
    TumTrajectoryWriter writer(abandoned);
    writer.Append(written[1]);
    EXPECT_EQ(ErrorOf([&] { writer.Append(written[0]); }).find(abandoned + ": pose 1 (time "), 0u);
  }
  EXPECT_FALSE(std::ifstream(abandoned).good());
  EXPECT_FALSE(std::ifstream(abandoned + ".tmp." + std::to_string(::getpid())).good());
  std::remove(whole.c_str());
  std::remove(streamed.c_str());
}

TEST(Trajectory, KittiRoundTripIsExactAndTimesFollowThePeriod) {
  const Trajectory written = RandomTrajectory(200, 2);
  const std::string path = TempPath("round_trip.kitti");
  WriteKittiTrajectory(path, written);
  const Trajectory read = ReadKittiTrajectory(path, 0.05);
  ExpectSamePoses(read, written, false);
  EXPECT_EQ(read[0].time, 0.0);
  EXPECT_EQ(read[3].time, 3 * 0.05);
  std::remove(path.c_str());
}

TEST(Trajectory, WritersNeverWriteNegativeZero) {
  // Negative zeros in times, translations and the rotation (a half turn about z, whose
  // quaternion and matrix have zeros computed from negative values).
  const Trajectory trajectory = {
      {-0.0, Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.0, 1.0, -0.0))},
      {1.0, Rigid3d::FromQuaternion(Eigen::Quaterniond(-0.0, -0.0, -0.0, -1.0), Eigen::Vector3d(-0.0, -0.0, -0.0))}};
  for (const bool kitti : {false, true}) {
    const std::string path = TempPath(kitti ? "zeros.kitti" : "zeros.tum");
    kitti ? WriteKittiTrajectory(path, trajectory) : WriteTumTrajectory(path, trajectory);
    std::ifstream in(path);
    std::string token;
    int zeros = 0;
    while (in >> token) {
      EXPECT_NE(token, "-0") << (kitti ? "KITTI" : "TUM");
      zeros += token == "0";
    }
    std::remove(path.c_str());
    EXPECT_GE(zeros, kitti ? 14 : 9) << "the zeros are written as 0";
  }
}

TEST(Trajectory, ReadsHandWrittenTum) {
  const Trajectory t = ReadTumTrajectory(kTestData + "handwritten.tum");
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0].time, 0.0);
  EXPECT_EQ(t[0].world_from_cam.rotation, Eigen::Matrix3d::Identity());
  EXPECT_EQ(t[0].world_from_cam.translation, Eigen::Vector3d::Zero());

  EXPECT_EQ(t[1].time, 0.1);
  EXPECT_EQ(t[1].world_from_cam.translation, Eigen::Vector3d(0.01, -0.002, 0.5));
  // q = (x 0, y 0.6, z 0, w 0.8): about y by theta with cos = 0.8^2 - 0.6^2, sin = 2 * 0.8 * 0.6.
  Eigen::Matrix3d r1;
  r1 << 0.28, 0, 0.96, 0, 1, 0, -0.96, 0, 0.28;
  EXPECT_TRUE(t[1].world_from_cam.rotation.isApprox(r1, 1e-15));

  EXPECT_EQ(t[2].time, 0.2);
  EXPECT_EQ(t[2].world_from_cam.translation, Eigen::Vector3d(0.001, 2.0, -3.5));
  // Slightly non-unit quaternion, normalised: 90 degrees about z.
  Eigen::Matrix3d r2;
  r2 << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_LT((t[2].world_from_cam.rotation - r2).norm(), 1e-15);
}

TEST(Trajectory, ReadsHandWrittenKitti) {
  const Trajectory t = ReadKittiTrajectory(kTestData + "handwritten.kitti");
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].time, 0.0);
  EXPECT_EQ(t[1].time, 0.1);
  EXPECT_EQ(t[0].world_from_cam.rotation, Eigen::Matrix3d::Identity());
  Eigen::Matrix3d r1;
  r1 << 0.8, 0, 0.6, 0, 1, 0, -0.6, 0, 0.8;
  EXPECT_LT((t[1].world_from_cam.rotation - r1).norm(), 1e-15);
  EXPECT_EQ(t[1].world_from_cam.translation, Eigen::Vector3d(0.01, -0.002, 0.5));
}

TEST(Trajectory, KittiRotationsPrintedWithFewDigitsAreProjected) {
  const std::string path = TempPath("six_digits.kitti");
  // 10 degrees about x, printed with 6 significant digits.
  WriteTextFileAtomically(path, "1 0 0 1 0 0.984808 -0.173648 2 0 0.173648 0.984808 3\n");
  const Rigid3d pose = ReadKittiTrajectory(path).at(0).world_from_cam;
  const Eigen::Matrix3d& r = pose.rotation;
  EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  EXPECT_NEAR(RotationAngle(r), 10.0 * M_PI / 180.0, 1e-6);
  std::remove(path.c_str());
}

TEST(Trajectory, MalformedTumNamesFileAndLine) {
  EXPECT_EQ(ReadErrorOf("# header\n0 0 0 0 0 0 0 1\n\n0.1 0 0 0 0 0 1\n"),
            ":4: expected 8 numbers (time tx ty tz qx qy qz qw), got 7");
  EXPECT_EQ(ReadErrorOf("0 0 0 0 0 0 0 1 5\n"), ":1: expected 8 numbers (time tx ty tz qx qy qz qw), got 9");
  EXPECT_EQ(ReadErrorOf("0 0 0 0 0 0 0 1\n0.1 0 0,5 0 0 0 0 1\n"), ":2: '0,5' is not a number");
  EXPECT_EQ(ReadErrorOf("0 0 nan 0 0 0 0 1\n"), ":1: non-finite value 'nan'");
  EXPECT_EQ(ReadErrorOf("0 0 0 0 0 0 0 inf\n"), ":1: non-finite value 'inf'");
  // Squares of 1e308 overflow: evaluate printed null statistics.
  EXPECT_EQ(ReadErrorOf("0 1e308 0 0 0 0 0 1\n"), ":1: translation 1e+308 beyond 1e+13 m");
  EXPECT_EQ(ReadErrorOf("0 0 0 0 0 0 0 0.5\n"), ":1: quaternion (qx qy qz qw) has norm 0.5, expected 1");
  EXPECT_EQ(ReadErrorOf("0.2 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 0 1\n"),
            ":2: time 0.1 is before the previous pose's time 0.2");
}

TEST(Trajectory, MalformedKittiNamesFileAndLine) {
  EXPECT_EQ(ReadErrorOf("1 0 0 0 0 1 0 0 0 0 1\n", true),
            ":1: expected 12 numbers (row-major 3x4 world_from_cam), got 11");
  EXPECT_EQ(ReadErrorOf("1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 -1 0\n", true),
            ":2: the left 3x3 block is not a rotation matrix (||R^T R - I|| = 0, det = -1)");
  EXPECT_EQ(ReadErrorOf("2 0 0 0 0 1 0 0 0 0 1 0\n", true),
            ":1: the left 3x3 block is not a rotation matrix (||R^T R - I|| = 3, det = 2)");
  EXPECT_EQ(ReadErrorOf("1 0 0 0 0 1 0 0 0 0 1 x\n", true), ":1: 'x' is not a number");
  EXPECT_EQ(ReadErrorOf("1 0 0 0 0 1 0 -2e13 0 0 1 0\n", true), ":1: translation -2e+13 beyond 1e+13 m");
}

TEST(Trajectory, MissingFileAndBadPeriod) {
  EXPECT_EQ(ErrorOf([] { ReadTumTrajectory("/nonexistent/a.tum"); }),
            "/nonexistent/a.tum: cannot open file (No such file or directory)");
  // A directory opens as a stream that reads nothing: it was an empty trajectory, without a name.
  const std::string dir = std::string(::testing::TempDir());
  EXPECT_EQ(ErrorOf([&] { ReadTumTrajectory(dir); }), dir + ": is a directory, expected a file");
  EXPECT_EQ(ErrorOf([] { ReadKittiTrajectory("/nonexistent/a.kitti", 0.0); }),
            "/nonexistent/a.kitti: KITTI frame period must be a finite number > 0, got 0");
}

TEST(Trajectory, WritersRejectWhatTheReadersWould) {
  Trajectory trajectory = RandomTrajectory(3, 3);
  trajectory[1].world_from_cam.translation.y() = std::nan("");
  const std::string path = TempPath("invalid.tum");
  EXPECT_NE(ErrorOf([&] { WriteTumTrajectory(path, trajectory); }).find(": pose 1 (time "), std::string::npos);
  EXPECT_NE(ErrorOf([&] { WriteKittiTrajectory(path, trajectory); }).find("): not finite"), std::string::npos);
  trajectory[1].world_from_cam.translation.y() = 1e300;
  EXPECT_NE(ErrorOf([&] { WriteTumTrajectory(path, trajectory); }).find("): translation beyond 1e+13 m"),
            std::string::npos);
  trajectory[1].world_from_cam.translation.y() = 0.0;
  trajectory[2].time = 0.0;
  EXPECT_EQ(ErrorOf([&] { WriteTumTrajectory(path, trajectory); }), path + ": pose 2 (time 0): time goes backwards");
  EXPECT_FALSE(std::ifstream(path).good()) << "a file was written";
}

TEST(Trajectory, PathLengthSumsTheStepsBetweenCameraCentres) {
  Trajectory t;
  EXPECT_EQ(PathLengthM(t), 0.0);
  for (const Eigen::Vector3d& c : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(3, 4, 0), Eigen::Vector3d(3, 4, 2)}) {
    t.push_back({0.0, Rigid3d(Eigen::Matrix3d::Identity(), c)});
  }
  EXPECT_DOUBLE_EQ(PathLengthM(t), 7.0);
}

}  // namespace
}  // namespace slt
