#include "methods/stereo_ekf/robust_pose_solver.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "geometry/se3.h"

namespace slt {
namespace {

// Features measuring two rows each (lines with one transfer degenerate), residuals linear in the
// pose's logarithm, r = A (Log(M) - d0) (+ an offset for the outliers), noise-free.
class TwoRowModel final : public FeatureModel {
 public:
  TwoRowModel(int count, const std::vector<int>& outliers) : a_(count), offset_(count, Eigen::Vector4d::Zero()) {
    std::mt19937_64 rng(5);
    std::normal_distribution<double> normal;
    for (auto& a : a_) a = Eigen::Matrix<double, 4, 6>::NullaryExpr([&]() { return normal(rng); });
    for (int i : outliers) offset_[i] << 0.5, -0.4, 0.0, 0.0;
    d0_ << 0.01, -0.02, 0.015, 0.02, 0.01, -0.01;
  }
  void Reset(const StereoRig&) override {}
  int SetReference(const StereoFrame&) override { return NumFeatures(); }
  int SetCurrent(const StereoFrame&) override { return NumFeatures(); }
  int NumFeatures() const override { return static_cast<int>(a_.size()); }
  int CurrentStereoFeatures() const override { return NumFeatures(); }
  bool Evaluate(int index, const Rigid3d& cam_from_ref, bool with_covariance, FeatureBlock* block) const override {
    block->residual = a_[index] * (LogSE3(cam_from_ref) - d0_) + offset_[index];
    block->jacobian = a_[index];
    if (with_covariance) block->covariance = 1e-6 * Eigen::Matrix4d::Identity();
    block->measured_rows = 0x3u;
    block->ClearUnmeasuredRows(with_covariance);
    return true;
  }
  Rigid3d Truth() const { return ExpSE3(d0_); }

 private:
  std::vector<Eigen::Matrix<double, 4, 6>> a_;
  std::vector<Eigen::Vector4d> offset_;
  Vector6d d0_;
};

TEST(RobustPoseSolver, SamplesEnoughTwoRowFeaturesToFixThePose) {
  // Two features of two rows give 4 equations for 6 unknowns: a hypothesis from them leaves two
  // directions where they started and agrees with no other feature. Three do fix the pose, so
  // the solver finds the 6 inliers among 8 and the exact pose.
  const TwoRowModel model(8, {2, 5});
  std::vector<WeightedFeature> features(model.NumFeatures());
  std::vector<int> valid;
  for (int i = 0; i < model.NumFeatures(); ++i) {
    ASSERT_TRUE(model.Evaluate(i, Rigid3d(), true, &features[i].block));
    ASSERT_TRUE(features[i].FactorCovariance());
    valid.push_back(i);
  }
  GateThresholds gate;
  gate.by_dimension[2] = 13.82;  // chi-square(2), 99.9 %
  gate.by_dimension[4] = 18.47;
  RobustPoseSolver solver;
  solver.Reset(1);
  RobustSolveResult result;
  solver.Solve(model, features, valid, {Rigid3d()}, gate, 200, 0.999, &result);
  ASSERT_TRUE(result.success);
  EXPECT_EQ(result.inliers.size(), 6u);
  EXPECT_LT(LogSE3(result.cam_from_ref * model.Truth().Inverse()).norm(), 1e-8);
}

}  // namespace
}  // namespace slt
