#include "geometry/plucker.h"

#include <gtest/gtest.h>

#include "geometry/numeric_jacobian.h"
#include "geometry/trifocal.h"

namespace slt {
namespace {

double AngleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return a.normalized().cross(b.normalized()).norm();
}

Eigen::Vector3d ImageOf(const Rigid3d& cam_from_ref, const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  const Eigen::Vector3d a = cam_from_ref * p, b = cam_from_ref * q;
  return (a / a.z()).cross(b / b.z());
}

const Rigid3d kRightFromLeft(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.1, 0.0, 0.0));
const Eigen::Vector3d kP(-0.1, 0.05, 0.5), kQ(0.12, -0.06, 0.62);

Rigid3d Motion() {
  return ExpSE3((Vector6d() << 0.03, -0.02, 0.01, 0.02, -0.015, 0.03).finished());
}

TEST(Pluecker, FromPlanesMatchesPlaneTransferAndJacobians) {
  const Eigen::Vector4d a(0.3, -0.5, 0.8, 0.2), b(-0.1, 0.7, 0.4, -0.6);
  Matrix64d da, db;
  const PlueckerLine line = PlueckerFromPlanes(a, b, &da, &db);
  EXPECT_LT((line.moment - LineFromPlanePair(a, b)).norm(), 1e-15);
  EXPECT_NEAR(line.moment.dot(line.direction), 0.0, 1e-14);  // Pluecker constraint
  const auto stack = [](const PlueckerLine& l) {
    return (Eigen::Matrix<double, 6, 1>() << l.moment, l.direction).finished();
  };
  const auto fa = [&](const Eigen::Vector4d& x) { return stack(PlueckerFromPlanes(x, b)); };
  const auto fb = [&](const Eigen::Vector4d& x) { return stack(PlueckerFromPlanes(a, x)); };
  EXPECT_LT((CentralDifferenceJacobian<6, 4>(fa, a) - da).norm(), 1e-9);
  EXPECT_LT((CentralDifferenceJacobian<6, 4>(fb, b) - db).norm(), 1e-9);
}

TEST(Pluecker, StereoPairLineIsTheThreeDLine) {
  const Eigen::Vector3d left = ImageOf(Rigid3d(), kP, kQ), right = ImageOf(kRightFromLeft, kP, kQ);
  Matrix63d dl, dr;
  double sine = 0.0;
  const PlueckerLine line = StereoPairLine(kRightFromLeft, left, right, &dl, &dr, &sine);
  EXPECT_LT(AngleBetween(line.direction, kQ - kP), 1e-12);
  // n = p x d for the same scale of d.
  const double scale = line.direction.norm() / (kQ - kP).norm();
  const double sign = line.direction.dot(kQ - kP) > 0 ? 1.0 : -1.0;
  EXPECT_LT((line.moment - sign * scale * kP.cross(kQ - kP)).norm(), 1e-12 * line.moment.norm());
  EXPECT_GT(sine, 0.05);
  const auto fl = [&](const Eigen::Vector3d& x) {
    const PlueckerLine l = StereoPairLine(kRightFromLeft, x, right);
    return (Eigen::Matrix<double, 6, 1>() << l.moment, l.direction).finished();
  };
  const auto fr = [&](const Eigen::Vector3d& x) {
    const PlueckerLine l = StereoPairLine(kRightFromLeft, left, x);
    return (Eigen::Matrix<double, 6, 1>() << l.moment, l.direction).finished();
  };
  EXPECT_LT((CentralDifferenceJacobian<6, 3>(fl, left) - dl).norm(), 1e-9);
  EXPECT_LT((CentralDifferenceJacobian<6, 3>(fr, right) - dr).norm(), 1e-9);
  // A horizontal line lies in the rig's epipolar plane: the pair does not define it.
  const Eigen::Vector3d h1(-0.1, 0.02, 0.5), h2(0.1, 0.02, 0.5);
  StereoPairLine(kRightFromLeft, ImageOf(Rigid3d(), h1, h2), ImageOf(kRightFromLeft, h1, h2), nullptr, nullptr,
                 &sine);
  EXPECT_LT(sine, 1e-12);
}

TEST(Pluecker, ImagesInTheCurrentPairEqualTheTensorTransfer) {
  const Rigid3d m = Motion();
  const PlueckerLine line = StereoPairLine(kRightFromLeft, ImageOf(Rigid3d(), kP, kQ), ImageOf(kRightFromLeft, kP, kQ));
  StereoLineImages images;
  ImageLineInStereoPair(kRightFromLeft, m, line, true, &images);
  EXPECT_LT(AngleBetween(images.left, ImageOf(m, kP, kQ)), 1e-12);
  EXPECT_LT(AngleBetween(images.right, ImageOf(kRightFromLeft * m, kP, kQ)), 1e-12);
  // Eq. 16-17 with the current left camera as the first view: views 2 and 3 are the reference
  // left and right cameras seen from it.
  const Rigid3d ref_from_cam = m.Inverse();
  const TrifocalTensor t = TrifocalTensorFromCameras(ref_from_cam.ToMatrix3x4(), (kRightFromLeft * ref_from_cam).ToMatrix3x4());
  EXPECT_LT(AngleBetween(TransferLine(t, ImageOf(Rigid3d(), kP, kQ), ImageOf(kRightFromLeft, kP, kQ)), images.left),
            1e-12);

  const auto pose = [&](const Vector6d& d) {
    StereoLineImages o;
    ImageLineInStereoPair(kRightFromLeft, ExpSE3(d) * m, line, false, &o);
    return (Eigen::Matrix<double, 6, 1>() << o.left, o.right).finished();
  };
  const Eigen::Matrix<double, 6, 6> jp = CentralDifferenceJacobian<6, 6>(pose, Vector6d::Zero());
  EXPECT_LT((jp.topRows<3>() - images.left_d_pose).norm(), 1e-9);
  EXPECT_LT((jp.bottomRows<3>() - images.right_d_pose).norm(), 1e-9);
  Eigen::Matrix<double, 6, 1> x;
  x << line.moment, line.direction;
  const auto of_line = [&](const Eigen::Matrix<double, 6, 1>& y) {
    StereoLineImages o;
    ImageLineInStereoPair(kRightFromLeft, m, {y.head<3>(), y.tail<3>()}, false, &o);
    return (Eigen::Matrix<double, 6, 1>() << o.left, o.right).finished();
  };
  const Eigen::Matrix<double, 6, 6> jl = CentralDifferenceJacobian<6, 6>(of_line, x);
  EXPECT_LT((jl.topRows<3>() - images.left_d_line).norm(), 1e-9);
  EXPECT_LT((jl.bottomRows<3>() - images.right_d_line).norm(), 1e-9);
}

}  // namespace
}  // namespace slt
