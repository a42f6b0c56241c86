#include "geometry/stereo_point.h"

#include <cmath>
#include <limits>

#include "geometry/se3.h"
#include "geometry/trifocal.h"

namespace slt {

StereoPointGeometry::StereoPointGeometry(const StereoRig& rig) {
  const PinholeCamera& l = rig.left;
  const PinholeCamera& r = rig.right;
  left_k_inverse_ << 1.0 / l.fx, 0.0, -l.cx / l.fx,  //
      0.0, 1.0 / l.fy, -l.cy / l.fy,                 //
      0.0, 0.0, 1.0;
  right_kt_ << r.fx, 0.0, 0.0,  //
      0.0, r.fy, 0.0,           //
      r.cx, r.cy, 1.0;
  const Rigid3d& e = rig.right_from_left;
  // Essential matrix [t]_x R: x'_n^T E x_n = 0; then F = K'^-T E K^-1.
  const Eigen::Matrix3d essential = Skew(e.translation) * e.rotation;
  fundamental_ = PixelFromNormalizedLineMatrix(r) * essential * left_k_inverse_;
  // A line l'_n of the right camera back-projects to the plane [R^T l'_n; t . l'_n] in the left
  // camera's frame (pi = E^T l', E as a 3x4 camera matrix).
  Eigen::Matrix<double, 4, 3> plane_from_normalized_line;
  plane_from_normalized_line.topRows<3>() = e.rotation.transpose();
  plane_from_normalized_line.row(3) = e.translation.transpose();
  plane_from_pixel_line_ = plane_from_normalized_line * right_kt_;
}

double StereoPointGeometry::EpipolarDistance(const Eigen::Vector2d& left, const Eigen::Vector2d& right) const {
  const Eigen::Vector3d line = fundamental_ * Homogeneous(left);
  const double norm = line.head<2>().norm();
  if (!(norm > 0.0)) return std::numeric_limits<double>::infinity();  // left point at the epipole
  return std::abs(line.dot(Homogeneous(right))) / norm;
}

Eigen::Vector3d StereoPointGeometry::TransferLine(const Eigen::Vector2d& left, const Eigen::Vector2d& right) const {
  return right_kt_ * PerpendicularLineThroughPoint(fundamental_ * Homogeneous(left), right);
}

void StereoPointGeometry::Point(const Eigen::Vector2d& left, const Eigen::Vector2d& right, bool with_jacobian,
                                ReferencePoint* out) const {
  const Eigen::Vector3d epipolar = fundamental_ * Homogeneous(left);  // in I'_1, pixels
  const Eigen::Vector3d line = PerpendicularLineThroughPoint(epipolar, right);
  const Eigen::Vector4d plane = plane_from_pixel_line_ * line;
  const Eigen::Vector3d ray = left_k_inverse_ * Homogeneous(left);  // z = 1
  // IntersectRayWithPlane(ray, plane) = [pi_4 ray; -n . ray], made Euclidean.
  const Eigen::Vector3d n = plane.head<3>();
  const double s = -n.dot(ray);
  const double inv_s = 1.0 / s;
  const double scale = plane(3) * inv_s;
  out->point = scale * ray;
  out->depth = scale;
  out->ray_plane_sine = std::abs(s) / (n.norm() * ray.norm());
  if (!with_jacobian) return;
  // X = (pi_4 / s) ray with s = -n . ray:
  //   dX/d ray = (pi_4 / s) I + (pi_4 / s^2) ray n^T,   dX/d pi = [(pi_4 / s^2) ray ray^T, ray / s].
  Eigen::Matrix3d d_ray = scale * Eigen::Matrix3d::Identity();
  d_ray.noalias() += (scale * inv_s) * ray * n.transpose();
  Eigen::Matrix<double, 3, 4> d_plane;
  d_plane.leftCols<3>().noalias() = (scale * inv_s) * ray * ray.transpose();
  d_plane.col(3) = inv_s * ray;
  const Eigen::Matrix<double, 3, 3> d_line = d_plane.lazyProduct(plane_from_pixel_line_);
  // l' = (-b, a, b u' - a v') for the epipolar line (a, b, c) and x' = (u', v').
  Eigen::Matrix3d line_d_epipolar;
  line_d_epipolar << 0.0, -1.0, 0.0,  //
      1.0, 0.0, 0.0,                  //
      -right.y(), right.x(), 0.0;
  Eigen::Matrix<double, 3, 2> line_d_right;
  line_d_right << 0.0, 0.0, 0.0, 0.0, epipolar.y(), -epipolar.x();
  // Left pixel: through the ray and through the epipolar line F x.
  out->point_d_pixels.leftCols<2>().noalias() =
      d_ray.lazyProduct(left_k_inverse_.leftCols<2>()) +
      d_line.lazyProduct(line_d_epipolar).lazyProduct(fundamental_.leftCols<2>());
  out->point_d_pixels.rightCols<2>().noalias() = d_line.lazyProduct(line_d_right);
}

bool StereoEndpointsSwapped(const StereoPointGeometry& geometry, const Segment2d& left, const Segment2d& right,
                            double ambiguity_px) {
  const Eigen::Vector2d a = left.head<2>(), b = left.tail<2>();
  const Eigen::Vector2d a2 = right.head<2>(), b2 = right.tail<2>();
  const double kept = geometry.EpipolarDistance(a, a2) + geometry.EpipolarDistance(b, b2);
  const double swapped = geometry.EpipolarDistance(a, b2) + geometry.EpipolarDistance(b, a2);
  if (std::abs(kept - swapped) >= ambiguity_px) return swapped < kept;
  // Along the epipolar lines the distances cannot tell: keep the directions agreeing.
  return (b2 - a2).dot(b - a) < 0.0;
}

bool TemporalEndpointsSwapped(const Segment2d& reference, const Segment2d& current) {
  return (current.tail<2>() - current.head<2>()).dot(reference.tail<2>() - reference.head<2>()) < 0.0;
}

}  // namespace slt
