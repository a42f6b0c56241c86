#include "evaluation/consistency.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>
#include <stdexcept>

namespace slt {
namespace {

// A covariance with correlations and mixed scales (mm and mrad), as a tracker reports it.
Matrix6d SomeCovariance() {
  Matrix6d a;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) a(i, j) = u(rng);
  }
  Matrix6d p = a * a.transpose() + 0.5 * Matrix6d::Identity();
  const Vector6d scale = (Vector6d() << 2e-3, 3e-3, 1e-3, 2e-3, 1e-3, 4e-3).finished();
  return scale.asDiagonal() * p * scale.asDiagonal();
}

// Ground truth turning and moving; estimates = truth perturbed by d ~ N(0, p_true) in the
// documented convention (true = Exp(d) * estimate, as cam_from_world).
void MakeRun(int n, const Matrix6d& p_true, Trajectory* gt, Trajectory* est) {
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  const Matrix6d l = p_true.llt().matrixL();
  gt->clear();
  est->clear();
  for (int k = 0; k < n; ++k) {
    Vector6d motion;
    motion << 0.3 * std::sin(0.01 * k), 0.1 * k / n, -0.2, 0.4 * std::cos(0.02 * k), 0.1, -0.3;
    const Rigid3d cam_from_world = ExpSE3(motion);
    Vector6d z;
    for (int i = 0; i < 6; ++i) z(i) = normal(rng);
    const Vector6d d = l * z;
    gt->push_back({0.1 * k, cam_from_world.Inverse()});
    est->push_back({0.1 * k, (ExpSE3(-d) * cam_from_world).Inverse()});
  }
}

TEST(Consistency, ConsistentCovarianceGivesTheDegreesOfFreedom) {
  const Matrix6d p = SomeCovariance();
  Trajectory gt, est;
  MakeRun(4000, p, &gt, &est);
  const ConsistencyErrors c = EvaluateConsistency(gt, est, std::vector<Matrix6d>(est.size(), p));
  EXPECT_EQ(c.used_poses, 4000u);
  // Mean of 4000 chi-square(k): standard deviation sqrt(2k / 4000), 0.055 for k = 6.
  EXPECT_NEAR(c.nees.mean, 6.0, 0.25);
  EXPECT_NEAR(c.nees_rot.mean, 3.0, 0.2);
  EXPECT_NEAR(c.nees_pos.mean, 3.0, 0.2);
  EXPECT_LT(c.beyond_3sigma_fraction, 0.006);  // 0.27 % expected
}

TEST(Consistency, OverconfidentCovarianceIsCaught) {
  const Matrix6d p = SomeCovariance();
  Trajectory gt, est;
  MakeRun(2000, p, &gt, &est);
  // Claiming half the standard deviation: NEES x4, far more errors beyond 3 sigma (13 %).
  const ConsistencyErrors c = EvaluateConsistency(gt, est, std::vector<Matrix6d>(est.size(), 0.25 * p));
  EXPECT_NEAR(c.nees.mean, 24.0, 1.5);
  EXPECT_NEAR(c.nees_pos.mean, 12.0, 1.0);
  EXPECT_GT(c.beyond_3sigma_fraction, 0.10);
}

TEST(Consistency, SkipsPosesWithoutCovarianceAndChecksSizes) {
  const Matrix6d p = SomeCovariance();
  Trajectory gt, est;
  MakeRun(10, p, &gt, &est);
  std::vector<Matrix6d> covariances(est.size(), p);
  covariances[0].setZero();  // a tracker without a covariance for this pose
  EXPECT_EQ(EvaluateConsistency(gt, est, covariances).used_poses, 9u);
  covariances.pop_back();
  EXPECT_THROW(EvaluateConsistency(gt, est, covariances), std::invalid_argument);
  EXPECT_THROW(EvaluateConsistency(gt, est, std::vector<Matrix6d>(est.size(), Matrix6d::Zero())),
               std::invalid_argument);
}

TEST(Consistency, NeesBandIsTheChiSquareIntervalOfTheMean) {
  const auto one = NeesBand(0.95, 6, 1);
  EXPECT_NEAR(one.first, 1.237344, 1e-5);
  EXPECT_NEAR(one.second, 14.449375, 1e-5);
  const auto ten = NeesBand(0.95, 6, 10);  // chi-square(60) / 10
  EXPECT_NEAR(ten.first, 4.0481748, 1e-5);
  EXPECT_NEAR(ten.second, 8.3297675, 1e-5);
  EXPECT_THROW(NeesBand(1.0, 6, 10), std::invalid_argument);
}

}  // namespace
}  // namespace slt
