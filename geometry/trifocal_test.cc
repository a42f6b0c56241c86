#include "geometry/trifocal.h"

#include <gtest/gtest.h>

#include <random>

#include "geometry/line2d.h"
#include "geometry/numeric_jacobian.h"

namespace slt {
namespace {

// A 3-D line through two points in the reference frame, seen by camera cam_from_ref.
Eigen::Vector3d ImageLine(const Rigid3d& cam_from_ref, const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  const Eigen::Vector3d a = cam_from_ref * p, b = cam_from_ref * q;
  return (a / a.z()).cross(b / b.z());
}

double LineAngleError(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return a.normalized().cross(b.normalized()).norm();
}

// pi = P^T l: the plane through the camera centre that projects to line l.
Eigen::Vector4d BackProjectLine(const Matrix34d& P, const Eigen::Vector3d& line) { return P.transpose() * line; }

struct Scene {
  Rigid3d right_from_left{Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.1, 0.0, 0.0)};
  Rigid3d cam_from_ref;
  Eigen::Vector3d p{-0.1, 0.05, 0.5}, q{0.12, -0.03, 0.6};

  Scene() {
    Vector6d xi;
    xi << 0.03, -0.02, 0.01, 0.02, -0.015, 0.03;
    cam_from_ref = ExpSE3(xi);
  }
  Eigen::Vector3d RefLeft() const { return ImageLine(Rigid3d(), p, q); }
  Eigen::Vector3d RefRight() const { return ImageLine(right_from_left, p, q); }
  Eigen::Vector3d CurLeft() const { return ImageLine(cam_from_ref, p, q); }
  Eigen::Vector3d CurRight() const { return ImageLine(right_from_left * cam_from_ref, p, q); }
};

TEST(Trifocal, TensorLineAndPointTransferAreExact) {
  const Scene s;
  const Rigid3d cur_right = s.right_from_left * s.cam_from_ref;
  const TrifocalTensor T = TrifocalTensorFromCameras(s.right_from_left.ToMatrix3x4(), s.cam_from_ref.ToMatrix3x4());
  EXPECT_LT(LineAngleError(TransferLine(T, s.RefRight(), s.CurLeft()), s.RefLeft()), 1e-12);
  const TrifocalTensor T2 = TrifocalTensorFromCameras(s.cam_from_ref.ToMatrix3x4(), cur_right.ToMatrix3x4());
  EXPECT_LT(LineAngleError(TransferLine(T2, s.CurLeft(), s.CurRight()), s.RefLeft()), 1e-12);

  // Point transfer: x in view 1, the perpendicular to its epipolar line through x' in view 2.
  const Eigen::Vector3d X(0.05, -0.04, 0.55);
  const Eigen::Vector3d x1 = X / X.z();
  const Eigen::Vector3d Xr = s.right_from_left * X;
  const Eigen::Vector3d Xt = s.cam_from_ref * X;
  const Eigen::Matrix3d essential = Skew(s.right_from_left.translation) * s.right_from_left.rotation;
  const Eigen::Vector3d epi = essential * x1;
  const Eigen::Vector3d l2 = PerpendicularLineThroughPoint(epi, (Xr / Xr.z()).head<2>());
  const Eigen::Vector3d x3 = TransferPoint(T, x1, l2);
  EXPECT_LT((x3.hnormalized() - Xt.hnormalized()).norm(), 1e-12);
  // The epipolar line itself makes the transfer vanish.
  EXPECT_LT(TransferPoint(T, x1, epi).norm(), 1e-12);
  // Plane form of the point transfer.
  const Eigen::Vector4d Xh = IntersectRayWithPlane(x1, BackProjectLine(s.right_from_left.ToMatrix3x4(), l2));
  EXPECT_LT((Xh.hnormalized() - X).norm(), 1e-12);
}

TEST(Trifocal, PlaneFormEqualsTensorForm) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n;
  for (int trial = 0; trial < 20; ++trial) {
    Matrix34d A, B;
    for (int i = 0; i < 12; ++i) A(i) = n(rng), B(i) = n(rng);
    const Eigen::Vector3d l2(n(rng), n(rng), n(rng)), l3(n(rng), n(rng), n(rng));
    const Eigen::Vector3d tensor = TransferLine(TrifocalTensorFromCameras(A, B), l2, l3);
    const Eigen::Vector3d planes = LineFromPlanePair(BackProjectLine(A, l2), BackProjectLine(B, l3));
    EXPECT_LT((tensor - planes).norm(), 1e-12 * (1.0 + tensor.norm()));
  }
}

TEST(Trifocal, PlaneToReferenceJacobian) {
  const Scene s;
  const Eigen::Vector4d plane(0.3, -0.5, 0.8, 0.2);
  const auto f = [&](const Vector6d& d) -> Eigen::Vector4d { return PlaneToReference(ExpSE3(d) * s.cam_from_ref, plane); };
  Matrix46d J;
  PlaneToReference(s.cam_from_ref, plane, &J);
  EXPECT_LT((CentralDifferenceJacobian<4, 6>(f, Vector6d::Zero()) - J).norm(), 1e-8);
  // A point on the plane stays on it.
  const Eigen::Vector3d X(0.1, 0.2, (-0.2 - 0.3 * 0.1 + 0.5 * 0.2) / 0.8);
  const Eigen::Vector4d pr = PlaneToReference(s.cam_from_ref, plane);
  EXPECT_NEAR(pr.head<3>().dot(s.cam_from_ref.Inverse() * X) + pr(3), 0.0, 1e-12);
}

TEST(Trifocal, LineFromPlanePairJacobians) {
  const Eigen::Vector4d a(0.3, -0.5, 0.8, 0.2), b(-0.1, 0.7, 0.4, -0.6);
  Eigen::Matrix<double, 3, 4> ja, jb;
  LineFromPlanePair(a, b, &ja, &jb);
  const auto fa = [&](const Eigen::Vector4d& x) -> Eigen::Vector3d { return LineFromPlanePair(x, b); };
  const auto fb = [&](const Eigen::Vector4d& x) -> Eigen::Vector3d { return LineFromPlanePair(a, x); };
  EXPECT_LT((CentralDifferenceJacobian<3, 4>(fa, a) - ja).norm(), 1e-9);
  EXPECT_LT((CentralDifferenceJacobian<3, 4>(fb, b) - jb).norm(), 1e-9);
}

TEST(Trifocal, StereoTransfersAreExactAndTheirJacobiansMatch) {
  const Scene s;
  CurrentToReferenceTransfer c2r;
  TransferCurrentToReference(s.right_from_left, s.cam_from_ref, s.RefRight(), s.CurLeft(), s.CurRight(),
                             true, &c2r);
  EXPECT_LT(LineAngleError(c2r.via_T, s.RefLeft()), 1e-12);
  EXPECT_LT(LineAngleError(c2r.via_Tprime, s.RefLeft()), 1e-12);

  using V6 = Vector6d;
  const auto c2r_pose = [&](const V6& d) -> Eigen::Matrix<double, 6, 1> {
    CurrentToReferenceTransfer o;
    TransferCurrentToReference(s.right_from_left, ExpSE3(d) * s.cam_from_ref, s.RefRight(), s.CurLeft(),
                               s.CurRight(), false, &o);
    return (Eigen::Matrix<double, 6, 1>() << o.via_T, o.via_Tprime).finished();
  };
  const Eigen::Matrix<double, 6, 6> jp = CentralDifferenceJacobian<6, 6>(c2r_pose, V6::Zero());
  EXPECT_LT((jp.topRows<3>() - c2r.via_T_d_pose).norm(), 1e-8);
  EXPECT_LT((jp.bottomRows<3>() - c2r.via_Tprime_d_pose).norm(), 1e-8);

  // Jacobians with respect to the lines: stack [ref_right; cur_left; cur_right].
  Eigen::Matrix<double, 9, 1> lines;
  lines << s.RefRight(), s.CurLeft(), s.CurRight();
  const auto c2r_lines = [&](const Eigen::Matrix<double, 9, 1>& x) -> Eigen::Matrix<double, 6, 1> {
    CurrentToReferenceTransfer o;
    TransferCurrentToReference(s.right_from_left, s.cam_from_ref, x.segment<3>(0), x.segment<3>(3),
                               x.segment<3>(6), false, &o);
    return (Eigen::Matrix<double, 6, 1>() << o.via_T, o.via_Tprime).finished();
  };
  const Eigen::Matrix<double, 6, 9> jl = CentralDifferenceJacobian<6, 9>(c2r_lines, lines);
  EXPECT_LT((jl.block<3, 3>(0, 0) - c2r.via_T_d_ref_right).norm(), 1e-8);
  EXPECT_LT((jl.block<3, 3>(0, 3) - c2r.via_T_d_cur_left).norm(), 1e-8);
  EXPECT_LT((jl.block<3, 3>(0, 6)).norm(), 1e-12);
  EXPECT_LT((jl.block<3, 3>(3, 0)).norm(), 1e-12);
  EXPECT_LT((jl.block<3, 3>(3, 3) - c2r.via_Tprime_d_cur_left).norm(), 1e-8);
  EXPECT_LT((jl.block<3, 3>(3, 6) - c2r.via_Tprime_d_cur_right).norm(), 1e-8);
}

}  // namespace
}  // namespace slt
