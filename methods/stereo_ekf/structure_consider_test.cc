#include "methods/stereo_ekf/structure_consider.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

namespace slt {
namespace {

using Matrix12d = StructureConsider::Matrix12d;
using Vector12d = StructureConsider::Vector12d;
constexpr int kU = FeatureModel::kStructureNoiseSize;

// Features with given structures and structure Jacobians (already whitened: the features'
// covariance factors are the identity).
class StructureStub final : public FeatureModel {
 public:
  std::vector<int> structure_of;
  std::vector<StructureJacobian> jacobians;
  int structures = 0;
  std::vector<int> versions;

  void Reset(const StereoRig&) override {}
  int SetReference(const StereoFrame&) override { return 0; }
  int SetCurrent(const StereoFrame&) override { return 0; }
  int NumFeatures() const override { return static_cast<int>(structure_of.size()); }
  int CurrentStereoFeatures() const override { return 0; }
  bool Evaluate(int, const Rigid3d&, bool, FeatureBlock*) const override { return false; }
  bool DescribesStructure() const override { return true; }
  int NumStructures() const override { return structures; }
  int StructureOf(int index) const override { return structure_of[index]; }
  int StructureVersion(int s) const override { return versions[s]; }
  bool EvaluateStructureJacobian(int index, const Rigid3d&, StructureJacobian* g) const override {
    *g = jacobians[index];
    return true;
  }
};

// The Schmidt update against the dense Kalman update of the joint state (e, u_0 .. u_n-1),
// Cov(u) = I, features r_i = J_i e_p + G_i u_s(i) + n_i with Cov(n_i) = I - G_i G_i^T (whitened):
// the state's correction and posterior covariance, and its cross-covariance with every u_s.
TEST(StructureConsiderTest, MatchesTheDenseKalmanUpdateOfTheJointState) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  auto random = [&](int rows, int cols, double scale) {
    return Eigen::MatrixXd(Eigen::MatrixXd::NullaryExpr(rows, cols, [&]() { return scale * normal(rng); }));
  };
  const int structures = 5;
  StructureStub model;
  model.structures = structures;
  model.versions.assign(structures, 0);
  model.structure_of = {0, 2, 3, 4};
  const int features = static_cast<int>(model.structure_of.size());
  for (int i = 0; i < features; ++i) model.jacobians.push_back(random(4, kU, 0.12));

  // A consistent joint prior: e = B u + c, c ~ N(0, P0), so Q = B and P = B B^T + P0. Scales
  // of the room loop: millimetres of pose, whitened Jacobians of hundreds per metre.
  const int nu = structures * kU;
  const Eigen::MatrixXd b = random(12, nu, 1e-3);
  const Eigen::MatrixXd c = random(12, 12, 1e-3);
  const Matrix12d p = b * b.transpose() + c * c.transpose();
  StructureConsider consider;
  consider.Reset(model);
  // Reach the cross-covariance B through Predict: Reset starts from zero, so load it by hand
  // through one exact update? Simpler: the test sets it (friend-free) by predicting a zero
  // state... instead, compare from Q = 0 and then from the Q the first update produced.
  std::vector<WeightedFeature> weighted(features);
  for (int i = 0; i < features; ++i) {
    weighted[i].sqrt_covariance.setIdentity();
    weighted[i].whitened_jacobian = random(4, 6, 300.0);
    weighted[i].whitened_residual = random(4, 1, 1.0);
  }
  (void)b;

  // Dense reference, run twice: two consecutive frames (the second starts from the cross-
  // covariance the first produced).
  Eigen::MatrixXd joint = Eigen::MatrixXd::Zero(12 + nu, 12 + nu);
  joint.topLeftCorner(12, 12) = p;
  joint.bottomRightCorner(nu, nu).setIdentity();
  for (int frame = 0; frame < 2; ++frame) {
    const int m = 4 * features;
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(m, 12 + nu);
    Eigen::MatrixXd r = Eigen::MatrixXd::Zero(m, m);
    Eigen::VectorXd nu_vec(m);
    for (int i = 0; i < features; ++i) {
      h.block(4 * i, 0, 4, 6) = weighted[i].whitened_jacobian;
      h.block(4 * i, 12 + kU * model.structure_of[i], 4, kU) = model.jacobians[i];
      r.block(4 * i, 4 * i, 4, 4) =
          Eigen::Matrix4d::Identity() - model.jacobians[i] * model.jacobians[i].transpose();
      nu_vec.segment<4>(4 * i) = -weighted[i].whitened_residual;
    }
    const Eigen::MatrixXd s = h * joint * h.transpose() + r;
    const Eigen::MatrixXd k = joint * h.transpose() * s.inverse();
    const Eigen::VectorXd expected_delta = k.topRows(12) * nu_vec;
    Eigen::MatrixXd expected = joint - k * s * k.transpose();

    std::vector<int> inliers(features);
    for (int i = 0; i < features; ++i) inliers[i] = i;
    for (int i = 0; i < features; ++i) ASSERT_TRUE(consider.Linearize(model, weighted[i], i, Rigid3d(), 1.0));
    Vector12d delta;
    Matrix12d posterior;
    ASSERT_TRUE(consider.Solve(weighted, inliers, joint.topLeftCorner(12, 12), Vector6d::Zero(), &delta, &posterior));
    consider.Commit(inliers);
    const double scale = p.norm();
    EXPECT_LT((delta - expected_delta).norm(), 1e-8 * expected_delta.norm()) << "frame " << frame;
    EXPECT_LT((posterior - expected.topLeftCorner(12, 12)).norm(), 1e-7 * scale) << "frame " << frame;
    for (int st = 0; st < structures; ++st) {
      EXPECT_LT((consider.cross_covariance(st) - expected.block(0, 12 + kU * st, 12, kU)).norm(), 1e-7 * std::sqrt(scale))
          << "frame " << frame << " structure " << st;
    }
    // Schmidt: the structure keeps its prior covariance; the next frame starts from there.
    expected.bottomRightCorner(nu, nu).setIdentity();
    joint = expected;
    for (int i = 0; i < features; ++i) weighted[i].whitened_residual = random(4, 1, 1.0);
  }
}

}  // namespace
}  // namespace slt
