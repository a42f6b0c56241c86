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
  const Eigen::Matrix3d& r = cam_from_ref.rotation;
  const Eigen::Vector3d& t = cam_from_ref.translation;
  // The line in the current left camera (TransformPluecker, inlined: this runs per line and
  // per iteration).
  const Eigen::Vector3d m = r * line_in_ref.direction;
  const Eigen::Vector3d n = r * line_in_ref.moment + t.cross(m);
  out->left = n;
  // Exp(d) moves the line as n += w x n + v x m, m += w x m:  d n / d [v; w] = [-[m]_x, -[n]_x].
  out->left_d_pose.leftCols<3>() = -Skew(m);
  out->left_d_pose.rightCols<3>() = -Skew(n);
  // Right camera: n_r = Re n + te x (Re m). With Re [a]_x = [Re a]_x Re:
  //   d n_r / d [v; w] = [-[Re m]_x Re, -([Re n]_x + [te]_x [Re m]_x) Re].
  const Eigen::Matrix3d& re = right_from_left.rotation;
  const Eigen::Vector3d& te = right_from_left.translation;
  const Eigen::Vector3d re_m = re * m, re_n = re * n;
  out->right = re_n + te.cross(re_m);
  const Eigen::Matrix3d re_m_x = Skew(re_m);
  out->right_d_pose.leftCols<3>().noalias() = -re_m_x * re;
  out->right_d_pose.rightCols<3>().noalias() = -(Skew(re_n) + Skew(te) * re_m_x) * re;
  if (with_line_jacobians) {
    // d n / d [n_ref; d_ref] = [R, [t]_x R];  d n_r = Re d n + [te]_x Re R d d_ref.
    out->left_d_line.leftCols<3>() = r;
    out->left_d_line.rightCols<3>().noalias() = Skew(t) * r;
    out->right_d_line.noalias() = re * out->left_d_line;
    out->right_d_line.rightCols<3>().noalias() += Skew(te) * (re * r);
  }
}

}  // namespace slt
