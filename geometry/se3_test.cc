#include "geometry/se3.h"

#include <gtest/gtest.h>

#include <random>

#include "geometry/numeric_jacobian.h"

namespace slt {
namespace {

Vector6d RandomTwist(std::mt19937& rng, double angle_scale, double translation_scale) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vector6d xi;
  for (int i = 0; i < 3; ++i) xi(i) = translation_scale * n(rng);
  for (int i = 3; i < 6; ++i) xi(i) = angle_scale * n(rng);
  return xi;
}

// Eq. 5 summed as a series, to check the closed form against the paper's definition.
Eigen::Matrix4d SeriesExp(const Vector6d& xi) {
  Eigen::Matrix4d sum = Eigen::Matrix4d::Identity(), term = Eigen::Matrix4d::Identity();
  for (int k = 1; k < 40; ++k) {
    term = term * Hat(xi) / k;
    sum += term;
  }
  return sum;
}

TEST(SE3, ExpMatchesSeriesOfEq5) {
  std::mt19937 rng(1);
  for (double scale : {1e-9, 1e-4, 1e-2, 0.3, 1.5}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Vector6d xi = RandomTwist(rng, scale, 1.0);
      EXPECT_LT((ExpSE3(xi).ToMatrix4() - SeriesExp(xi)).norm(), 1e-12) << "scale " << scale;
    }
  }
}

TEST(SE3, LogInvertsExpIncludingNearZeroAndNearPi) {
  std::mt19937 rng(2);
  for (double scale : {0.0, 1e-10, 1e-5, 5e-3, 0.2, 1.0}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Vector6d xi = RandomTwist(rng, scale, 0.5);
      EXPECT_LT((LogSE3(ExpSE3(xi)) - xi).norm(), 1e-10) << "scale " << scale;
    }
  }
  // Rotation angle just below pi.
  Vector6d xi;
  xi << 0.1, -0.2, 0.3, 0.0, (M_PI - 1e-6), 0.0;
  EXPECT_LT((LogSE3(ExpSE3(xi)) - xi).norm(), 1e-6);
}

TEST(SE3, RotationAngle) {
  EXPECT_NEAR(RotationAngle(ExpSO3(Eigen::Vector3d(0.0, 0.0, 0.5))), 0.5, 1e-14);
  EXPECT_NEAR(RotationAngle(ExpSO3(Eigen::Vector3d(1e-9, 0.0, 0.0))), 1e-9, 1e-20);
  EXPECT_NEAR(RotationAngle(ExpSO3(Eigen::Vector3d(0.0, M_PI, 0.0))), M_PI, 1e-12);
}

TEST(SE3, CompositionAndInverse) {
  std::mt19937 rng(3);
  const Rigid3d a = ExpSE3(RandomTwist(rng, 0.7, 1.0));
  const Rigid3d b = ExpSE3(RandomTwist(rng, 0.7, 1.0));
  EXPECT_LT(((a * b).ToMatrix4() - a.ToMatrix4() * b.ToMatrix4()).norm(), 1e-12);
  EXPECT_LT(((a * a.Inverse()).ToMatrix4() - Eigen::Matrix4d::Identity()).norm(), 1e-12);
  const Eigen::Vector3d p(0.3, -1.0, 2.0);
  EXPECT_LT((a * (b * p) - (a * b) * p).norm(), 1e-12);
  EXPECT_LT((a.Center() - a.Inverse().translation).norm(), 1e-12);
}

TEST(SE3, AdjointConjugates) {
  std::mt19937 rng(4);
  const Rigid3d t = ExpSE3(RandomTwist(rng, 0.8, 1.0));
  const Vector6d xi = RandomTwist(rng, 0.3, 0.2);
  const Rigid3d lhs = t * ExpSE3(xi) * t.Inverse();
  const Rigid3d rhs = ExpSE3(Adjoint(t) * xi);
  EXPECT_LT((lhs.ToMatrix4() - rhs.ToMatrix4()).norm(), 1e-12);
}

TEST(SE3, SO3LeftJacobianMatchesCentralDifferences) {
  std::mt19937 rng(5);
  for (double scale : {1e-6, 5e-3, 0.02, 0.5, 2.0}) {
    const Eigen::Vector3d w = RandomTwist(rng, scale, 0.0).tail<3>();
    const Eigen::Matrix3d R0 = ExpSO3(w);
    const auto f = [&](const Eigen::Vector3d& d) -> Eigen::Vector3d {
      return LogSO3(ExpSO3(w + d) * R0.transpose());
    };
    const Eigen::Matrix3d numeric = CentralDifferenceJacobian<3, 3>(f, Eigen::Vector3d::Zero());
    EXPECT_LT((numeric - LeftJacobianSO3(w)).norm(), 1e-8) << "scale " << scale;
    EXPECT_LT((LeftJacobianInverseSO3(w) * LeftJacobianSO3(w) - Eigen::Matrix3d::Identity()).norm(),
              1e-12);
  }
}

TEST(SE3, SE3LeftAndRightJacobiansMatchCentralDifferences) {
  std::mt19937 rng(6);
  for (double scale : {1e-7, 3e-3, 0.011, 0.4, 1.5}) {
    const Vector6d xi = RandomTwist(rng, scale, 0.7);
    const Rigid3d T0 = ExpSE3(xi);
    const auto left = [&](const Vector6d& d) -> Vector6d {
      return LogSE3(ExpSE3(xi + d) * T0.Inverse());
    };
    const Matrix6d jl = CentralDifferenceJacobian<6, 6>(left, Vector6d::Zero());
    EXPECT_LT((jl - LeftJacobianSE3(xi)).norm(), 1e-8) << "scale " << scale;
  }
}

TEST(SE3, FirstOrderLeftJacobianIsExactToFirstOrder) {
  for (double scale : {1e-3, 1e-2}) {
    Vector6d xi;
    xi << 0.3, -0.2, 0.5, 0.4, -0.1, 0.2;
    xi *= scale;
    const double err = (LeftJacobianSE3FirstOrder(xi) - LeftJacobianSE3(xi)).norm();
    EXPECT_LT(err, xi.squaredNorm());
    EXPECT_GT(err, 0.0);
  }
}

TEST(SE3, FirstOrderFormAgreesToFirstOrder) {
  Vector6d xi;
  xi << 0.01, -0.02, 0.005, 0.004, -0.01, 0.02;
  const Rigid3d exact = ExpSE3(xi), approx = FirstOrderSE3(xi);
  // Eq. 12 differs from eq. 5 at second order only: |difference| ~ |xi|^2 / 2, a hundredth of it
  // at xi / 10 (a first-order mistake, e.g. a flipped sign, would be ~|xi| and scale by 10).
  const double err = (exact.ToMatrix4() - approx.ToMatrix4()).norm();
  EXPECT_LT(err, xi.squaredNorm());
  const double err_tenth = (ExpSE3(0.1 * xi).ToMatrix4() - FirstOrderSE3(0.1 * xi).ToMatrix4()).norm();
  EXPECT_NEAR(err / err_tenth, 100.0, 5.0);
  EXPECT_LT((approx.rotation.transpose() * approx.rotation - Eigen::Matrix3d::Identity()).norm(),
            1e-14);
}

}  // namespace
}  // namespace slt
