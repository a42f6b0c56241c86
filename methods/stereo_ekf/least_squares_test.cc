#include "methods/stereo_ekf/least_squares.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "geometry/se3.h"
#include "methods/stereo_ekf/linear_test_model.h"

namespace slt {
namespace {

// A random symmetric positive-definite 6x6 matrix with condition number around 1e4, the range
// of a pose information matrix mixing radians and metres.
Matrix6d RandomSpd(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Matrix6d a;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) a(i, j) = normal(rng);
  Vector6d scale;
  scale << 1.0, 3.0, 10.0, 30.0, 60.0, 100.0;
  return scale.asDiagonal() * (a * a.transpose() + 0.1 * Matrix6d::Identity()) * scale.asDiagonal();
}

TEST(SpdSolver6, SolveInverseAndNormAgreeWithEigen) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 20; ++trial) {
    const Matrix6d a = RandomSpd(rng);
    Vector6d b;
    for (int i = 0; i < 6; ++i) b(i) = normal(rng);
    SpdSolver6 solver;
    ASSERT_TRUE(solver.Compute(a));
    const Eigen::LLT<Matrix6d> reference(a);
    const Vector6d x = solver.Solve(b);
    EXPECT_LT((x - reference.solve(b)).norm(), 1e-10 * (1.0 + x.norm()));
    EXPECT_LT((a * x - b).norm(), 1e-9 * (1.0 + b.norm()));
    EXPECT_LT((solver.Inverse() * a - Matrix6d::Identity()).norm(), 1e-9);
    // The lower factor reproduces a, and SquaredNorm is the quadratic form.
    const Matrix6d l = solver.lower();
    EXPECT_LT((l * l.transpose() - a).norm(), 1e-10 * a.norm());
    const double quadratic = b.dot(a * b);
    EXPECT_NEAR(solver.SquaredNorm(b), quadratic, 1e-12 * quadratic);
  }
}

TEST(SpdSolver6, RejectsMatricesThatAreNotPositiveDefinite) {
  Matrix6d a = Matrix6d::Identity();
  a(3, 3) = -1.0;
  SpdSolver6 solver;
  EXPECT_FALSE(solver.Compute(a));
  Matrix6d inverse;
  EXPECT_FALSE(InvertSpd6(a, &inverse));
  a(3, 3) = 0.0;  // singular
  EXPECT_FALSE(solver.Compute(a));
  a(3, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(solver.Compute(a));
}

TEST(InvertSpd6, InvertsPositiveDefiniteMatrices) {
  std::mt19937_64 rng(11);
  const Matrix6d a = RandomSpd(rng);
  Matrix6d inverse;
  ASSERT_TRUE(InvertSpd6(a, &inverse));
  EXPECT_LT((a * inverse - Matrix6d::Identity()).norm(), 1e-9);
}

TEST(FeatureBlock, RestrictToKeepsASupersetAndRejectsALostRow) {
  FeatureBlock block;
  block.residual << 1.0, 2.0, 3.0, 4.0;
  block.jacobian.setOnes();
  block.measured_rows = FeatureBlock::kAllRows;
  EXPECT_TRUE(block.RestrictTo(0xCu));  // rows 2-3 of a whitener built for them
  EXPECT_EQ(block.measured_rows, 0xCu);
  EXPECT_EQ(block.Dimension(), 2);
  EXPECT_EQ(block.residual, Eigen::Vector4d(0.0, 0.0, 3.0, 4.0));
  EXPECT_EQ(block.jacobian.topRows<2>().norm(), 0.0);
  EXPECT_EQ(block.jacobian.bottomRows<2>().sum(), 12.0);
  EXPECT_FALSE(block.RestrictTo(0x3u));  // rows 0-1 are no longer measured
  EXPECT_FALSE(block.RestrictTo(FeatureBlock::kAllRows));
}

// Three features measuring `rows_at_start` at M = I and `rows_away` elsewhere; feature 2 keeps
// all its rows everywhere.
LinearTestModel RowsByPoseModel(unsigned rows_at_start, unsigned rows_away) {
  LinearTestModel model(3, 3, 0.01);
  for (int i = 0; i < 2; ++i) {
    model.feature(i).rows_at_start = rows_at_start;
    model.feature(i).rows_away = rows_away;
  }
  return model;
}

std::vector<WeightedFeature> WhitenedAtStart(const FeatureModel& model) {
  std::vector<WeightedFeature> features;
  EXPECT_TRUE(WhitenedFeaturesAt(model, Rigid3d(), &features));
  return features;
}

TEST(RowsThatChangeWithThePose, AFeatureGainingRowsKeepsThoseItWasWhitenedFor) {
  // Whitened on rows 2-3 at the start, all four measured away from it: the cost and the solve
  // use rows 2-3 only, exactly as for a feature that never gains the rows.
  const LinearTestModel gaining = RowsByPoseModel(0xCu, FeatureBlock::kAllRows), fixed = RowsByPoseModel(0xCu, 0xCu);
  const std::vector<WeightedFeature> features = WhitenedAtStart(gaining);
  const Rigid3d away = ExpSE3((Vector6d() << 0.003, 0.001, -0.002, 0.004, 0.0, 0.002).finished());
  double cost_gaining, cost_fixed;
  ASSERT_TRUE(WhitenedCost(gaining, features[0], 0, away, &cost_gaining));
  ASSERT_TRUE(WhitenedCost(fixed, features[0], 0, away, &cost_fixed));
  EXPECT_GT(cost_fixed, 0.0);
  EXPECT_EQ(cost_gaining, cost_fixed);

  const int indices[3] = {0, 1, 2};
  Rigid3d pose_gaining, pose_fixed;
  Matrix6d information_gaining, information_fixed;
  ASSERT_TRUE(RefinePose(gaining, features, indices, 3, 10, &pose_gaining, &information_gaining));
  ASSERT_TRUE(RefinePose(fixed, features, indices, 3, 10, &pose_fixed, &information_fixed));
  EXPECT_LT(LogSE3(pose_gaining * gaining.Truth().Inverse()).norm(), 1e-9);  // noise-free: exact
  EXPECT_LT(LogSE3(pose_gaining * pose_fixed.Inverse()).norm(), 1e-12);
  EXPECT_LT((information_gaining - information_fixed).norm(), 1e-9 * information_fixed.norm());
}

TEST(RowsThatChangeWithThePose, AFeatureLosingARowCannotBeWhitenedThere) {
  // Whitened on all four rows at the start, rows 2-3 only away from it: no cost there, and a
  // solve that moves away fails rather than whiten it with a factor of other rows.
  const LinearTestModel losing = RowsByPoseModel(FeatureBlock::kAllRows, 0xCu);
  const std::vector<WeightedFeature> features = WhitenedAtStart(losing);
  const Rigid3d away = ExpSE3((Vector6d() << 0.003, 0.001, -0.002, 0.004, 0.0, 0.002).finished());
  double cost = 0.0;
  EXPECT_TRUE(WhitenedCost(losing, features[2], 2, away, &cost));  // feature 2 keeps its rows
  EXPECT_FALSE(WhitenedCost(losing, features[0], 0, away, &cost));
  const int indices[3] = {0, 1, 2};
  Rigid3d pose;
  Matrix6d information;
  EXPECT_FALSE(RefinePose(losing, features, indices, 3, 10, &pose, &information));
  // Control: the same features keeping their rows solve.
  const LinearTestModel keeping = RowsByPoseModel(FeatureBlock::kAllRows, FeatureBlock::kAllRows);
  pose = Rigid3d();
  EXPECT_TRUE(RefinePose(keeping, WhitenedAtStart(keeping), indices, 3, 10, &pose, &information));
}

TEST(RefinePose, MaxSigmaLeavesABarelyObservedDirectionWhereItStarted) {
  // Three noisy features that see translation y (the second twist component) only through a
  // factor 0.02 of their other directions, as vertical lines see the height: the LDLT solve
  // moves along that direction by the noise divided by the small pivot; with max_sigma it stays
  // where it started (M = I) and the five directions determined better than max_sigma are solved
  // alike.
  LinearTestModel model(3, 3, 1e-4);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal;
  for (int i = 0; i < model.NumFeatures(); ++i) {
    model.feature(i).a.col(1) *= 0.02;
    for (int r = 0; r < 4; ++r) model.feature(i).offset(r) = 0.01 * normal(rng);
  }
  std::vector<WeightedFeature> features;
  ASSERT_TRUE(WhitenedFeaturesAt(model, Rigid3d(), &features));
  const int indices[3] = {0, 1, 2};
  const double max_sigma = 0.05;
  Rigid3d solved, kept;
  Matrix6d information;
  ASSERT_TRUE(RefinePose(model, features, indices, 3, 10, &solved, &information));
  ASSERT_TRUE(RefinePose(model, features, indices, 3, 10, &kept, &information, max_sigma));
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(information);
  ASSERT_GT(1.0 / std::sqrt(eigen.eigenvalues()(0)), max_sigma);  // one direction weaker
  ASSERT_LT(1.0 / std::sqrt(eigen.eigenvalues()(1)), max_sigma);  // five stronger
  const Vector6d weak = eigen.eigenvectors().col(0);
  EXPECT_GT(std::abs(weak(1)), 0.99);  // it is the height
  const Vector6d d_true = LogSE3(model.Truth()), d_solved = LogSE3(solved), d_kept = LogSE3(kept);
  EXPECT_GT(std::abs(weak.dot(d_solved - d_true)), 5.0 * std::abs(weak.dot(d_true)));  // moved by the noise
  EXPECT_LT(std::abs(weak.dot(d_kept)), 1e-4);                                           // kept at the start
  for (int d = 1; d < 6; ++d) {
    EXPECT_NEAR(eigen.eigenvectors().col(d).dot(d_kept), eigen.eigenvectors().col(d).dot(d_solved), 1e-4) << d;
  }
}

}  // namespace
}  // namespace slt
