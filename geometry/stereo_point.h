// The epipolar geometry of a stereo rig for points (pixel coordinates): the distance of a point
// to an epipolar line, the pairing of two segments' endpoints, and a point of the left image
// placed by its right partner: X = the left ray of x met by the plane E^T l' that back-projects
// l', the right image's line through x' perpendicular to x's epipolar line F x (Hartley &
// Zisserman's point transfer through a line, Sec. 15.1.1; in a rectified rig, l' is the column
// through x' and X the point at the disparity u - u'). Yu's point-trifocal EKF measures such
// points (methods/yu_point_ekf); trifocal_line_ekf places the lines of an epipolar plane by
// their endpoints (line_transfer_model.h).
#pragma once

#include <Eigen/Core>

#include "geometry/camera.h"
#include "geometry/line2d.h"

namespace slt {

// A reference point: x's ray met by the plane E^T l'.
struct ReferencePoint {
  Eigen::Vector3d point;                       // X in the reference left camera frame (m)
  Eigen::Matrix<double, 3, 4> point_d_pixels;  // d X / d [x; x'] (pixel coordinates)
  double depth = 0.0;                          // X.z
  double ray_plane_sine = 0.0;                 // sine of the angle between the ray and the plane
};

// The epipolar geometry of a rig, for point transfer and endpoint pairing (pixel coordinates).
class StereoPointGeometry {
 public:
  StereoPointGeometry() = default;
  explicit StereoPointGeometry(const StereoRig& rig);

  // F with x'^T F x = 0 for homogeneous pixel points x (left) and x' (right):
  // F = K'^-T [t_E]_x R_E K^-1.
  const Eigen::Matrix3d& fundamental() const { return fundamental_; }
  // Distance (px) of the right point to the epipolar line of the left point.
  double EpipolarDistance(const Eigen::Vector2d& left, const Eigen::Vector2d& right) const;
  // l' of the transfer, in the right camera's normalised coordinates (K'^T of the pixel line).
  Eigen::Vector3d TransferLine(const Eigen::Vector2d& left, const Eigen::Vector2d& right) const;
  // X with its Jacobian with respect to the pixels (when `with_jacobian`).
  void Point(const Eigen::Vector2d& left, const Eigen::Vector2d& right, bool with_jacobian,
             ReferencePoint* out) const;

 private:
  Eigen::Matrix3d fundamental_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d left_k_inverse_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d right_kt_ = Eigen::Matrix3d::Identity();  // K'^T: pixel lines -> normalised
  // pi' = plane_from_pixel_line_ * l'_pixel = E^T K'^T l'_pixel (4x3).
  Eigen::Matrix<double, 4, 3> plane_from_pixel_line_ = Eigen::Matrix<double, 4, 3>::Zero();
};

// True when a line's endpoints pair across the rig as (a <-> b', b <-> a') instead of (a <-> a',
// b <-> b'): that pairing's epipolar distances sum to at least ambiguity_px less; within it (a
// line along the epipolar lines, where the distances cannot tell) when the segments point
// opposite ways.
bool StereoEndpointsSwapped(const StereoPointGeometry& geometry, const Segment2d& left, const Segment2d& right,
                            double ambiguity_px);
// True when the current segment runs the other way along the line from the reference one.
bool TemporalEndpointsSwapped(const Segment2d& reference, const Segment2d& current);

}  // namespace slt
