#include "optim/line_sfm_manifolds.h"

#include <ceres/manifold_test_utils.h>
#include <gtest/gtest.h>

#include <random>

#include "geometry/se3.h"

namespace slt {
namespace {

constexpr double kTolerance = 1e-9;

// Ceres's checks of Plus, Minus and their Jacobians against each other and against numeric
// differentiation (ceres/manifold_test_utils.h).
void ExpectInvariants(const ceres::Manifold& manifold, const ceres::Vector& x, const ceres::Vector& delta,
                      const ceres::Vector& y) {
  using namespace ceres;  // the macro names Ceres's matchers unqualified
  EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, x, delta, y, kTolerance);
}

Vector6d RandomTwist(std::mt19937_64& rng, double scale) {
  std::normal_distribution<double> n(0.0, scale);
  Vector6d xi;
  for (int i = 0; i < 6; ++i) xi(i) = n(rng);
  return xi;
}

ceres::Vector PoseVector(const Rigid3d& pose) {
  ceres::Vector x(kPoseAmbientSize);
  PoseToParameters(pose, x.data());
  return x;
}

// A line through `point` with direction `direction`, as manifold parameters.
ceres::Vector LineVector(const Eigen::Vector3d& point, const Eigen::Vector3d& direction) {
  ceres::Vector x(kLineAmbientSize);
  EXPECT_TRUE(LineToParameters({point.cross(direction), direction}, x.data()));
  return x;
}

ceres::Vector RandomLine(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return LineVector(Eigen::Vector3d(n(rng), n(rng), n(rng) + 2.0), Eigen::Vector3d(n(rng), n(rng), n(rng)));
}

TEST(PoseManifold, PlusIsTheLeftPerturbationOfTheConventions) {
  std::mt19937_64 rng(1);
  const PoseManifold manifold;
  for (int trial = 0; trial < 10; ++trial) {
    const Rigid3d pose = ExpSE3(RandomTwist(rng, 1.0));
    const Vector6d delta = RandomTwist(rng, 0.3);
    double out[kPoseAmbientSize];
    ASSERT_TRUE(manifold.Plus(PoseVector(pose).data(), delta.data(), out));
    const Rigid3d expected = ExpSE3(delta) * pose;
    EXPECT_LT((PoseFromParameters(out).ToMatrix4() - expected.ToMatrix4()).norm(), 1e-12);
  }
}

TEST(PoseManifold, InvariantsHold) {
  std::mt19937_64 rng(2);
  const PoseManifold manifold;
  for (int trial = 0; trial < 10; ++trial) {
    const ceres::Vector x = PoseVector(ExpSE3(RandomTwist(rng, 1.0)));
    const ceres::Vector y = PoseVector(ExpSE3(RandomTwist(rng, 1.0)));
    const ceres::Vector delta = RandomTwist(rng, 0.3);
    ExpectInvariants(manifold, x, delta, y);
  }
}

TEST(LineManifold, InvariantsHold) {
  std::mt19937_64 rng(3);
  const LineManifold manifold;
  std::normal_distribution<double> n(0.0, 0.3);
  for (int trial = 0; trial < 10; ++trial) {
    const ceres::Vector x = RandomLine(rng);
    // y near x, with the opposite orientation half of the time (Minus is then near a half turn).
    ceres::Vector y(kLineAmbientSize);
    const ceres::Vector step = (ceres::Vector(4) << n(rng), n(rng), n(rng), n(rng)).finished();
    ASSERT_TRUE(manifold.Plus(x.data(), step.data(), y.data()));
    if (trial % 2) y = -y;
    const ceres::Vector delta = (ceres::Vector(4) << n(rng), n(rng), n(rng), n(rng)).finished();
    ExpectInvariants(manifold, x, delta, y);
  }
}

TEST(LineManifold, PlusKeepsAUnitDirectionAndAValidPlueckerLine) {
  std::mt19937_64 rng(4);
  const LineManifold manifold;
  ceres::Vector x = RandomLine(rng);
  std::normal_distribution<double> n(0.0, 0.5);
  for (int step = 0; step < 100; ++step) {
    const Eigen::Vector4d delta(n(rng), n(rng), n(rng), n(rng));
    ceres::Vector y(kLineAmbientSize);
    ASSERT_TRUE(manifold.Plus(x.data(), delta.data(), y.data()));
    x = y;
  }
  const PlueckerLine line = LineFromParameters(x.data());
  EXPECT_NEAR(line.direction.norm(), 1.0, 1e-12);
  EXPECT_NEAR(line.moment.dot(line.direction), 0.0, 1e-12);
}

TEST(LineManifold, RegularForALineThroughTheOrigin) {
  // Where Bartoli & Sturm's (U, W) update loses a rank (zero moment), Taylor's does not: the
  // Plus Jacobian keeps four singular values of 1 (a unit direction, a zero moment).
  const LineManifold manifold;
  const ceres::Vector x = LineVector(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.3, -0.2, 1.0));
  Eigen::Matrix<double, 6, 4, Eigen::RowMajor> jacobian;
  ASSERT_TRUE(manifold.PlusJacobian(x.data(), jacobian.data()));
  const Eigen::Vector4d singular = Eigen::JacobiSVD<Eigen::MatrixXd>(jacobian).singularValues();
  EXPECT_NEAR(singular.minCoeff(), 1.0, 1e-12);
  EXPECT_NEAR(singular.maxCoeff(), 1.0, 1e-12);
  std::mt19937_64 rng(5);
  const ceres::Vector delta = ceres::Vector::Constant(4, 0.1);
  const ceres::Vector y = RandomLine(rng);
  ExpectInvariants(manifold, x, delta, y);
}

TEST(LineParameters, RejectALineWithoutDirection) {
  double parameters[kLineAmbientSize] = {7, 7, 7, 7, 7, 7};
  EXPECT_FALSE(LineToParameters({Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::Zero()}, parameters));
  EXPECT_FALSE(LineToParameters({Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(NAN, 0, 1)}, parameters));
  EXPECT_EQ(parameters[0], 7.0);
}

TEST(NormalPlaneBasis, IsRightHandedAndOrthonormal) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  for (const Eigen::Vector3d& d : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 0, -1),
                                   Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized()}) {
    Eigen::Vector3d e1, e2;
    NormalPlaneBasis(d, &e1, &e2);
    Eigen::Matrix3d basis;
    basis << e1, e2, d;
    EXPECT_LT((basis.transpose() * basis - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(basis.determinant(), 1.0, 1e-12);
  }
}

// The tangent basis is the manifold's Plus Jacobian, and its left pseudo-inverse undoes it on a
// line with a moment (where the basis is not orthonormal).
TEST(LineTangentBasis, IsThePlusJacobianAndItsPseudoInverseUndoesIt) {
  std::mt19937_64 rng(9);
  const ceres::Vector x = RandomLine(rng);
  Eigen::Matrix<double, 6, 4, Eigen::RowMajor> jacobian;
  ASSERT_TRUE(LineManifold().PlusJacobian(x.data(), jacobian.data()));
  const Eigen::Matrix<double, 6, 4> basis = LineTangentBasis(x.data());
  EXPECT_EQ((basis - jacobian).norm(), 0.0);
  EXPECT_GT((basis.transpose() * basis - Eigen::Matrix4d::Identity()).norm(), 1e-3);
  EXPECT_LT((LineTangentFromAmbient(basis) * basis - Eigen::Matrix4d::Identity()).norm(), 1e-12);
}

}  // namespace
}  // namespace slt
