#include "geometry/plucker.h"

namespace slt {

PlueckerLine PlueckerFromPlanes(const Eigen::Vector4d& a, const Eigen::Vector4d& b, Matrix64d* d_a,
                                Matrix64d* d_b) {
  const Eigen::Vector3d na = a.head<3>(), nb = b.head<3>();
  if (d_a) {
    d_a->topLeftCorner<3, 3>() = b(3) * Eigen::Matrix3d::Identity();
    d_a->topRightCorner<3, 1>() = -nb;
    d_a->bottomLeftCorner<3, 3>() = Skew(nb);  // d(nb x na)/d na = [nb]_x
    d_a->bottomRightCorner<3, 1>().setZero();
  }
  if (d_b) {
    d_b->topLeftCorner<3, 3>() = -a(3) * Eigen::Matrix3d::Identity();
    d_b->topRightCorner<3, 1>() = na;
    d_b->bottomLeftCorner<3, 3>() = -Skew(na);
    d_b->bottomRightCorner<3, 1>().setZero();
  }
  return {na * b(3) - a(3) * nb, nb.cross(na)};
}

PlueckerLine TransformPluecker(const Rigid3d& b_from_a, const PlueckerLine& line, Matrix36d* moment_d_line) {
  const Eigen::Vector3d rd = b_from_a.rotation * line.direction;
  if (moment_d_line) {
    moment_d_line->leftCols<3>() = b_from_a.rotation;
    moment_d_line->rightCols<3>() = Skew(b_from_a.translation) * b_from_a.rotation;
  }
  return {b_from_a.rotation * line.moment + b_from_a.translation.cross(rd), rd};
}

PlueckerLine StereoPairLine(const Rigid3d& right_from_left, const Eigen::Vector3d& left_line,
                            const Eigen::Vector3d& right_line, Matrix63d* d_left, Matrix63d* d_right,
                            double* plane_sine) {
  // Back-projected planes in the left frame: [l; 0] and E^T [l'; 0] = [Re^T l'; te . l'].
  Eigen::Vector4d a, b;
  a << left_line, 0.0;
  b << right_from_left.rotation.transpose() * right_line, right_from_left.translation.dot(right_line);
  Matrix64d da, db;
  const PlueckerLine line = PlueckerFromPlanes(a, b, d_left ? &da : nullptr, d_right ? &db : nullptr);
  if (d_left) *d_left = da.leftCols<3>();
  if (d_right) {
    Eigen::Matrix<double, 4, 3> b_d_line;
    b_d_line.topRows<3>() = right_from_left.rotation.transpose();
    b_d_line.row(3) = right_from_left.translation.transpose();
    *d_right = db * b_d_line;
  }
  if (plane_sine) *plane_sine = line.direction.norm() / (a.head<3>().norm() * b.head<3>().norm());
  return line;
}

void ImageLineInStereoPair(const Rigid3d& right_from_left, const Rigid3d& cam_from_ref,
                           const PlueckerLine& line_in_ref, bool with_line_jacobians, StereoLineImages* out) {
  const Rigid3d right_from_ref = right_from_left * cam_from_ref;
  const PlueckerLine in_left = TransformPluecker(cam_from_ref, line_in_ref);
  const PlueckerLine in_right = TransformPluecker(right_from_ref, line_in_ref);
  out->left = in_left.moment;
  out->right = in_right.moment;
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  out->left_d_pose = ImageLinePoseJacobianProduct<3>(identity, in_left);
  // E Exp(d) M = Exp(Ad_E d) E M: the right camera is perturbed by Ad_E d.
  out->right_d_pose = ImageLinePoseJacobianProduct<3>(identity, in_right) * Adjoint(right_from_left);
  if (with_line_jacobians) {
    out->left_d_line = ImageLineLineJacobianProduct<3>(identity, cam_from_ref);
    out->right_d_line = ImageLineLineJacobianProduct<3>(identity, right_from_ref);
  }
}

}  // namespace slt
