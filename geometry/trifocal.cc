#include "geometry/trifocal.h"

namespace slt {
namespace {

// d(pi_in_ref)/d(line) for a plane q = [Re^T l; te . l] (back-projection through the right camera
// of a rig, expressed in the left camera's frame).
Eigen::Matrix<double, 4, 3> RightCameraBackProjection(const Rigid3d& right_from_left) {
  Eigen::Matrix<double, 4, 3> m;
  m.topRows<3>() = right_from_left.rotation.transpose();
  m.row(3) = right_from_left.translation.transpose();
  return m;
}

// M^T restricted to 4x4 acting on planes: [R^T 0; t^T 1].
Eigen::Matrix4d PlaneToReferenceMatrix(const Rigid3d& cam_from_ref) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m.topLeftCorner<3, 3>() = cam_from_ref.rotation.transpose();
  m.bottomLeftCorner<1, 3>() = cam_from_ref.translation.transpose();
  m(3, 3) = 1.0;
  return m;
}

}  // namespace

TrifocalTensor TrifocalTensorFromCameras(const Matrix34d& A, const Matrix34d& B) {
  TrifocalTensor t;
  for (int i = 0; i < 3; ++i) {
    t.slices[i] = A.col(i) * B.col(3).transpose() - A.col(3) * B.col(i).transpose();
  }
  return t;
}

Eigen::Vector3d TransferLine(const TrifocalTensor& tensor, const Eigen::Vector3d& line2,
                             const Eigen::Vector3d& line3) {
  Eigen::Vector3d l;
  for (int i = 0; i < 3; ++i) l(i) = line2.dot(tensor.slices[i] * line3);
  return l;
}

Eigen::Vector3d TransferPoint(const TrifocalTensor& tensor, const Eigen::Vector3d& point1,
                              const Eigen::Vector3d& line2) {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) x += point1(i) * (tensor.slices[i].transpose() * line2);
  return x;
}

Eigen::Vector3d PerpendicularLineThroughPoint(const Eigen::Vector3d& epipolar_line,
                                              const Eigen::Vector2d& point) {
  const double a = epipolar_line.x(), b = epipolar_line.y();
  return {-b, a, b * point.x() - a * point.y()};
}

double PlaneAngleSine(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
  const Eigen::Vector3d na = a.head<3>(), nb = b.head<3>();
  return na.cross(nb).norm() / (na.norm() * nb.norm());
}

Eigen::Vector3d LineFromPlanePair(const Eigen::Vector4d& plane2, const Eigen::Vector4d& plane3,
                                  Eigen::Matrix<double, 3, 4>* d_plane2,
                                  Eigen::Matrix<double, 3, 4>* d_plane3) {
  if (d_plane2) {
    d_plane2->leftCols<3>() = plane3(3) * Eigen::Matrix3d::Identity();
    d_plane2->col(3) = -plane3.head<3>();
  }
  if (d_plane3) {
    d_plane3->leftCols<3>() = -plane2(3) * Eigen::Matrix3d::Identity();
    d_plane3->col(3) = plane2.head<3>();
  }
  return plane2.head<3>() * plane3(3) - plane2(3) * plane3.head<3>();
}

Eigen::Vector4d PlaneToReference(const Rigid3d& cam_from_ref, const Eigen::Vector4d& plane_in_cam,
                                 Matrix46d* d_delta) {
  const Eigen::Vector3d n = plane_in_cam.head<3>();
  const Eigen::Matrix3d rt = cam_from_ref.rotation.transpose();
  if (d_delta) {
    // Exp(d)^T [n; s] ~= [n; s] + [n x w; n . v], then M^T = [R^T 0; t^T 1].
    const Eigen::Matrix3d n_x = Skew(n);
    d_delta->topLeftCorner<3, 3>().setZero();
    d_delta->topRightCorner<3, 3>() = rt * n_x;
    d_delta->bottomLeftCorner<1, 3>() = n.transpose();
    d_delta->bottomRightCorner<1, 3>() = cam_from_ref.translation.transpose() * n_x;
  }
  Eigen::Vector4d out;
  out.head<3>() = rt * n;
  out(3) = cam_from_ref.translation.dot(n) + plane_in_cam(3);
  return out;
}

Eigen::Vector4d IntersectRayWithPlane(const Eigen::Vector3d& point1, const Eigen::Vector4d& plane) {
  Eigen::Vector4d X;
  X.head<3>() = plane(3) * point1;
  X(3) = -plane.head<3>().dot(point1);
  return X;
}

void TransferCurrentToReference(const Rigid3d& right_from_left, const Rigid3d& cam_from_ref,
                                const Eigen::Vector3d& ref_right, const Eigen::Vector3d& cur_left,
                                const Eigen::Vector3d& cur_right, bool with_jacobians,
                                CurrentToReferenceTransfer* out) {
  const Eigen::Matrix<double, 4, 3> right_bp = RightCameraBackProjection(right_from_left);
  // Plane of the reference right line (the reference frame is the reference left camera).
  const Eigen::Vector4d p_ref_right = right_bp * ref_right;
  // Planes of the current left and right lines, in the current left camera, then in the reference.
  Eigen::Vector4d q_left;
  q_left << cur_left, 0.0;
  const Eigen::Vector4d q_right = right_bp * cur_right;
  Matrix46d j_left, j_right;
  Matrix46d* jl = with_jacobians ? &j_left : nullptr;
  Matrix46d* jr = with_jacobians ? &j_right : nullptr;
  const Eigen::Vector4d p_left = PlaneToReference(cam_from_ref, q_left, jl);
  const Eigen::Vector4d p_right = PlaneToReference(cam_from_ref, q_right, jr);

  Eigen::Matrix<double, 3, 4> a2, a3, b2, b3;
  out->via_T = LineFromPlanePair(p_ref_right, p_left, with_jacobians ? &a2 : nullptr,
                                 with_jacobians ? &a3 : nullptr);
  out->via_Tprime = LineFromPlanePair(p_left, p_right, with_jacobians ? &b2 : nullptr,
                                      with_jacobians ? &b3 : nullptr);
  out->via_T_plane_sine = PlaneAngleSine(p_ref_right, p_left);
  out->via_Tprime_plane_sine = PlaneAngleSine(p_left, p_right);
  if (!with_jacobians) return;
  const Eigen::Matrix4d to_ref = PlaneToReferenceMatrix(cam_from_ref);
  const Eigen::Matrix<double, 4, 3> d_pleft_d_line = to_ref.leftCols<3>();
  out->via_T_d_pose = a3 * j_left;
  out->via_T_d_ref_right = a2 * right_bp;
  out->via_T_d_cur_left = a3 * d_pleft_d_line;
  out->via_Tprime_d_pose = b2 * j_left + b3 * j_right;
  out->via_Tprime_d_cur_left = b2 * d_pleft_d_line;
  out->via_Tprime_d_cur_right = b3 * (to_ref * right_bp);
}

}  // namespace slt
