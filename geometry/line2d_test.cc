#include "geometry/line2d.h"

#include <gtest/gtest.h>

#include "geometry/numeric_jacobian.h"

namespace slt {
namespace {

TEST(Line2d, LineThroughPointsContainsThemAndJacobian) {
  const Eigen::Vector4d seg(10.0, 20.0, 300.0, -40.0);
  Eigen::Matrix<double, 3, 4> J;
  const Eigen::Vector3d l = LineFromSegment(seg, &J);
  EXPECT_NEAR(l.dot(Homogeneous(seg.head<2>())), 0.0, 1e-9);
  EXPECT_NEAR(l.dot(Homogeneous(seg.tail<2>())), 0.0, 1e-9);
  const auto f = [](const Eigen::Vector4d& s) -> Eigen::Vector3d { return LineFromSegment(s); };
  EXPECT_LT((CentralDifferenceJacobian<3, 4>(f, seg) - J).norm(), 1e-6);
}

TEST(Line2d, NormalisationWithIntrinsicsMatchesEq6) {
  PinholeCamera cam{800.0, 820.0, 310.0, 250.0};
  const Eigen::Vector2d p1(100.0, 50.0), p2(400.0, 420.0);
  const Eigen::Vector3d l = LineThroughPoints(p1, p2);
  const Eigen::Vector3d ln = NormalizedLineFromPixelLine(cam, l);
  // The normalised line holds the normalised points.
  EXPECT_NEAR(ln.dot(Homogeneous(cam.PixelToNormalized(p1))), 0.0, 1e-9);
  EXPECT_NEAR(ln.dot(Homogeneous(cam.PixelToNormalized(p2))), 0.0, 1e-9);
  // Eq. 6 with f = fx = fy is the same line up to the scale f^2.
  PinholeCamera square{800.0, 800.0, 310.0, 250.0};
  const Eigen::Vector3d eq6(l.x() / 800.0, l.y() / 800.0,
                            (l.z() + 310.0 * l.x() + 250.0 * l.y()) / (800.0 * 800.0));
  EXPECT_LT((NormalizedLineFromPixelLine(square, l) / (800.0 * 800.0) - eq6).norm(), 1e-12);
  // Round trip and the matrix form.
  EXPECT_LT((PixelLineFromNormalizedLine(cam, ln) - l).norm(), 1e-9 * l.norm());
  EXPECT_LT((PixelFromNormalizedLineMatrix(cam) * ln - l).norm(), 1e-9 * l.norm());
}

TEST(Line2d, SignedDistanceAndJacobians) {
  const Eigen::Vector3d l(0.6, 0.8, -5.0);
  const Eigen::Vector2d p(3.0, 4.0);
  Eigen::Matrix<double, 1, 3> dl;
  Eigen::Matrix<double, 1, 2> dp;
  EXPECT_NEAR(SignedDistance(l, p, &dl, &dp), 0.0, 1e-12);
  EXPECT_NEAR(SignedDistance(2.0 * l, Eigen::Vector2d(3.6, 4.8)), 1.0, 1e-12);
  const Eigen::Vector3d l2(0.3, -2.0, 7.0);
  SignedDistance(l2, p, &dl, &dp);
  const auto fl = [&](const Eigen::Vector3d& x) -> Eigen::Matrix<double, 1, 1> {
    return Eigen::Matrix<double, 1, 1>(SignedDistance(x, p));
  };
  const auto fp = [&](const Eigen::Vector2d& x) -> Eigen::Matrix<double, 1, 1> {
    return Eigen::Matrix<double, 1, 1>(SignedDistance(l2, x));
  };
  EXPECT_LT((CentralDifferenceJacobian<1, 3>(fl, l2) - dl).norm(), 1e-8);
  EXPECT_LT((CentralDifferenceJacobian<1, 2>(fp, p) - dp).norm(), 1e-8);
}

TEST(Line2d, ThetaLambdaHasNoSingularDirection) {
  // Every direction, including the vertical and horizontal ones that break eq. 8-9.
  for (double angle = -M_PI; angle < M_PI; angle += M_PI / 8) {
    const Eigen::Vector3d l(std::cos(angle), std::sin(angle), -2.5);
    const Eigen::Vector2d tl = ThetaLambdaFromLine(3.0 * l);
    EXPECT_NEAR(WrapAngle(tl.x() - angle), 0.0, 1e-12);
    EXPECT_NEAR(tl.y(), 2.5, 1e-12);
    Eigen::Matrix<double, 2, 3> J;
    ThetaLambdaFromLine(l, &J);
    const auto f = [](const Eigen::Vector3d& x) -> Eigen::Vector2d {
      Eigen::Vector2d v = ThetaLambdaFromLine(x);
      return v;
    };
    const Eigen::Matrix<double, 2, 3> numeric = CentralDifferenceJacobian<2, 3>(f, l);
    // Skip the theta row where atan2 jumps across +-pi in the finite difference.
    if (std::abs(std::abs(angle) - M_PI) > 1e-3) {
      EXPECT_LT((numeric - J).norm(), 1e-7) << angle;
    }
  }
}

TEST(Line2d, ThetaLambdaResidualIgnoresSignAndWraps) {
  const Eigen::Vector3d measured(-1.0, 1e-3, 10.0);  // normal near +-pi
  const Eigen::Vector3d predicted(1.0, 2e-3, -10.2);
  const Eigen::Vector2d r1 = ThetaLambdaResidual(measured, predicted);
  const Eigen::Vector2d r2 = ThetaLambdaResidual(measured, -predicted);
  EXPECT_LT((r1 - r2).norm(), 1e-14);
  EXPECT_NEAR(r1.x(), -3e-3, 1e-6);  // theta difference across the +-pi wrap, not ~2 pi
  EXPECT_NEAR(r1.y(), 0.2, 1e-3);
  Eigen::Matrix<double, 2, 3> J;
  ThetaLambdaResidual(measured, predicted, &J);
  const auto f = [&](const Eigen::Vector3d& x) -> Eigen::Vector2d {
    return ThetaLambdaResidual(measured, x);
  };
  EXPECT_LT((CentralDifferenceJacobian<2, 3>(f, predicted) - J).norm(), 1e-7);
  EXPECT_LT(ThetaLambdaResidual(measured, measured).norm(), 1e-15);
}

}  // namespace
}  // namespace slt
