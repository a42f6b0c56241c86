#include "evaluation/report.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

namespace slt {
namespace {

// n poses 0.1 s apart moving along x, starting at time `start`.
Trajectory Straight(int n, double start = 0.0) {
  Trajectory trajectory;
  for (int k = 0; k < n; ++k) {
    trajectory.push_back({start + 0.1 * k, Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.01 * k, 0, 0))});
  }
  return trajectory;
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(ErrorTable, OneRowPerMetricWithUnitsAndEvosStatistics) {
  const Trajectory gt = Straight(11);
  Trajectory est = gt;
  // Translation errors 0, 1, ..., 10 mm along y: rmse sqrt(35) mm, mean = median 5 mm,
  // std sqrt(10) mm, min 0, max 10 mm; each step is 1 mm off (RPE 1 mm), no rotation error.
  for (size_t k = 0; k < est.size(); ++k) est[k].world_from_cam.translation.y() = 0.001 * k;
  const std::vector<std::string> lines = Lines(ErrorTable(EvaluateTrajectory(gt, est, EvaluationOptions{})));
  ASSERT_EQ(lines.size(), 8u) << ErrorTable(EvaluateTrajectory(gt, est, EvaluationOptions{}));
  EXPECT_EQ(lines[0], "associated 11 of 11 estimate and 11 of 11 ground-truth poses (max time difference 0.01 s); "
                      "alignment none");
  EXPECT_EQ(lines[1], "metric                       rmse       mean     median        std        min        max");
  EXPECT_EQ(lines[2], "ATE translation (m)      0.005916   0.005000   0.005000   0.003162   0.000000   0.010000");
  EXPECT_EQ(lines[3], "ATE rotation (deg)       0.000000   0.000000   0.000000   0.000000   0.000000   0.000000");
  EXPECT_EQ(lines[4], "RPE translation (m)      0.001000   0.001000   0.001000   0.000000   0.001000   0.001000");
  EXPECT_EQ(lines[5].rfind("RPE rotation (deg) ", 0), 0u);
  EXPECT_EQ(lines[6], "RPE: 10 pairs (i, i + 1), i = 0, 1, 2, ...");
  EXPECT_EQ(lines[7], "final error (frame 10, time 1 s): translation 0.010000 m, rotation 0.000000 deg");
}

TEST(ErrorTable, NamesTheAlignmentAndItsScale) {
  Trajectory gt = Straight(10);
  for (size_t k = 0; k < gt.size(); ++k) gt[k].world_from_cam.translation.z() = 0.01 * (k % 3);
  Trajectory est = gt;
  for (TimedPose& pose : est) pose.world_from_cam.translation *= 0.5;
  EvaluationOptions options;
  options.alignment = Alignment::kSim3;
  const std::string table = ErrorTable(EvaluateTrajectory(gt, est, options));
  EXPECT_NE(table.find("; alignment sim3 (scale 2)\n"), std::string::npos) << table;
  options.alignment = Alignment::kSE3;
  options.rpe_all_pairs = true;
  options.rpe_delta_frames = 2;
  const std::string se3 = ErrorTable(EvaluateTrajectory(gt, est, options));
  EXPECT_NE(se3.find("; alignment se3\n"), std::string::npos) << se3;
  EXPECT_NE(se3.find("RPE: 8 pairs (i, i + 2), every i\n"), std::string::npos) << se3;
}

TEST(AssociationWarning, SilentWhenBothTrajectoriesAreCovered) {
  const Trajectory gt = Straight(100);
  EXPECT_EQ(AssociationWarning(EvaluateTrajectory(gt, gt, EvaluationOptions{})), "");
  // 95 of 100 ground-truth poses: exactly at the threshold.
  const Trajectory est(gt.begin(), gt.begin() + 95);
  EXPECT_EQ(AssociationWarning(EvaluateTrajectory(gt, est, EvaluationOptions{})), "");
}

TEST(AssociationWarning, NamesTheTrajectoryThatIsShort) {
  const Trajectory gt = Straight(100);
  // The case: another run's 600 estimate poses, 100 of them at the ground truth's times.
  Trajectory est = Straight(600, -30.0);
  const std::string many = AssociationWarning(EvaluateTrajectory(gt, est, EvaluationOptions{}));
  EXPECT_EQ(many, "only 100 of 600 estimate poses (16.7 %) are associated with a ground-truth pose within 0.01 s: "
                  "the errors describe part of the run only, or two different runs (below 95 % of either "
                  "trajectory)");
  // 94 of the ground truth's 100 poses.
  const Trajectory few(gt.begin(), gt.begin() + 94);
  const std::string short_gt = AssociationWarning(EvaluateTrajectory(gt, few, EvaluationOptions{}));
  EXPECT_EQ(short_gt.rfind("only 94 of 100 ground-truth poses (94.0 %) with an estimate pose: ", 0), 0u) << short_gt;
  // Both short.
  Trajectory both = Straight(200, -5.0);
  const std::string two = AssociationWarning(EvaluateTrajectory(few, both, EvaluationOptions{}));
  EXPECT_NE(two.find("only 94 of 200 estimate poses (47.0 %) are associated"), std::string::npos) << two;
  EXPECT_EQ(two.find("ground-truth poses ("), std::string::npos) << "all 94 ground-truth poses are associated: " << two;
  // A stricter threshold warns on the 95 %.
  const Trajectory est95(gt.begin(), gt.begin() + 95);
  EXPECT_NE(AssociationWarning(EvaluateTrajectory(gt, est95, EvaluationOptions{}), 0.99), "");
}

}  // namespace
}  // namespace slt
