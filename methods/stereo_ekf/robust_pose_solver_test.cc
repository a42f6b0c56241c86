#include "methods/stereo_ekf/robust_pose_solver.h"

#include <gtest/gtest.h>

#include <numeric>
#include <vector>

#include "geometry/se3.h"
#include "methods/stereo_ekf/linear_test_model.h"

namespace slt {
namespace {

// Eight features measuring two rows each (lines with one transfer degenerate), two of them
// outliers.
LinearTestModel TwoRowModel() {
  LinearTestModel model(8, 5, 1e-6);
  for (int i = 0; i < model.NumFeatures(); ++i) model.feature(i).rows_at_start = model.feature(i).rows_away = 0x3u;
  for (int i : {2, 5}) model.feature(i).offset << 0.5, -0.4, 0.0, 0.0;
  return model;
}

TEST(RobustPoseSolver, SamplesEnoughTwoRowFeaturesToFixThePose) {
  // Two features of two rows give 4 equations for 6 unknowns: a hypothesis from them leaves two
  // directions where they started and agrees with no other feature. Three do fix the pose, so
  // the solver finds the 6 inliers among 8 and the exact pose.
  const LinearTestModel model = TwoRowModel();
  std::vector<WeightedFeature> features;
  ASSERT_TRUE(WhitenedFeaturesAt(model, Rigid3d(), &features));
  std::vector<int> valid(model.NumFeatures());
  std::iota(valid.begin(), valid.end(), 0);
  GateThresholds gate;
  gate.by_dimension[2] = 13.82;  // chi-square(2), 99.9 %
  gate.by_dimension[4] = 18.47;
  RobustPoseSolver solver;
  solver.Reset(1);
  RobustSolveResult result;
  solver.Solve(model, features, valid, {Rigid3d()}, gate, {200, 0.999}, 0.0, &result);
  ASSERT_TRUE(result.success);
  EXPECT_EQ(result.inliers.size(), 6u);
  EXPECT_LT(LogSE3(result.cam_from_ref * model.Truth().Inverse()).norm(), 1e-8);
}

}  // namespace
}  // namespace slt
