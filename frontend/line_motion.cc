#include "frontend/line_motion.h"

#include <cmath>

namespace slt {
namespace {

// H = K (R - t n^T / d) K^-1 for the plane n^T X + d = 0 of the previous camera's frame.
Eigen::Matrix3d PlaneHomography(const PinholeCamera& camera, const Rigid3d& next_from_previous,
                                const Eigen::Vector3d& n, double d) {
  const Eigen::Matrix3d k = camera.K();
  const Eigen::Matrix3d motion = next_from_previous.rotation - next_from_previous.translation * n.transpose() / d;
  return k * motion * k.inverse();
}

// Depth along the ray of normalised point x (x, y, 1) to the plane n^T X + d = 0.
double DepthOnPlane(const Eigen::Vector3d& n, double d, const Eigen::Vector3d& x) { return -d / n.dot(x); }

// The right camera's back-projected plane of `right`, in the left frame: n^T X + d = 0.
void RightPlaneInLeft(const StereoRig& rig, const Segment2d& right, Eigen::Vector3d* n, double* d) {
  const Eigen::Vector3d n_right = NormalizedLineFromPixelLine(rig.right, LineFromSegment(right)).normalized();
  // X_r = E X_l: n = R_E^T n_r, d = n_r . t_E.
  *n = rig.right_from_left.rotation.transpose() * n_right;
  *d = n_right.dot(rig.right_from_left.translation);
}

// The points of the left segment's endpoints on the plane n^T X + d = 0 (left frame), as
// StereoSegmentEndpoints states.
bool EndpointsOnPlane(const StereoRig& rig, const Segment2d& left, const Eigen::Vector3d& n, double d,
                      Eigen::Vector3d* first, Eigen::Vector3d* second) {
  for (int e = 0; e < 2; ++e) {
    const Eigen::Vector2d xy = rig.left.PixelToNormalized(left.segment<2>(2 * e));
    const Eigen::Vector3d ray(xy.x(), xy.y(), 1.0);
    const double depth = DepthOnPlane(n, d, ray);
    const Eigen::Vector3d point = depth * ray;
    if (!(depth > 0.0) || !std::isfinite(depth) || !((rig.right_from_left * point).z() > 0.0)) return false;
    (e == 0 ? *first : *second) = point;
  }
  return true;
}

}  // namespace

bool StereoSegmentEndpoints(const StereoRig& rig, const Segment2d& left, const Segment2d& right,
                            Eigen::Vector3d* first, Eigen::Vector3d* second) {
  Eigen::Vector3d n;
  double d;
  RightPlaneInLeft(rig, right, &n, &d);
  return EndpointsOnPlane(rig, left, n, d, first, second);
}

bool PredictStereoLineMotion(const StereoRig& rig, const Rigid3d& next_from_previous, const Segment2d& left,
                             const Segment2d& right, double min_plane_sine, StereoLineMaps* maps, double* depth) {
  const Rigid3d& right_from_left = rig.right_from_left;
  const Rigid3d left_from_right = right_from_left.Inverse();
  // Back-projected planes through each camera's centre, in that camera's frame: [n; 0].
  const Eigen::Vector3d n_left = NormalizedLineFromPixelLine(rig.left, LineFromSegment(left)).normalized();
  // The right plane in the left frame; the left plane in the right frame likewise with E^-1.
  Eigen::Vector3d n_right_in_left;
  double d_right_in_left;
  RightPlaneInLeft(rig, right, &n_right_in_left, &d_right_in_left);
  const Eigen::Vector3d n_left_in_right = left_from_right.rotation.transpose() * n_left;
  const double d_left_in_right = n_left.dot(left_from_right.translation);
  if (n_left.cross(n_right_in_left).norm() < min_plane_sine) return false;
  Eigen::Vector3d first, second;
  if (!EndpointsOnPlane(rig, left, n_right_in_left, d_right_in_left, &first, &second)) return false;
  if (depth) *depth = 0.5 * (first.z() + second.z());
  const Rigid3d right_motion = right_from_left * next_from_previous * left_from_right;
  maps->left = PlaneHomography(rig.left, next_from_previous, n_right_in_left, d_right_in_left);
  maps->right = PlaneHomography(rig.right, right_motion, n_left_in_right, d_left_in_right);
  return maps->left.allFinite() && maps->right.allFinite();
}

StereoLineMaps FrontoParallelMaps(const StereoRig& rig, const Rigid3d& next_from_previous, double depth) {
  // z = depth: n = (0, 0, 1), d = -depth in the left frame; in the right frame (X_l = E^-1 X_r)
  // n_r = R_E n, d_r = d - n_r . t_E.
  const Rigid3d& e = rig.right_from_left;
  const Eigen::Vector3d n(0.0, 0.0, 1.0);
  const Eigen::Vector3d n_right = e.rotation * n;
  const double d_right = -depth - n_right.dot(e.translation);
  const Rigid3d right_motion = e * next_from_previous * e.Inverse();
  StereoLineMaps maps;
  maps.left = PlaneHomography(rig.left, next_from_previous, n, -depth);
  maps.right = PlaneHomography(rig.right, right_motion, n_right, d_right);
  return maps;
}

StereoLineMaps RotationOnlyMaps(const StereoRig& rig, const Rigid3d& next_from_previous) {
  const Rigid3d right_motion = rig.right_from_left * next_from_previous * rig.right_from_left.Inverse();
  StereoLineMaps maps;
  maps.left = rig.left.K() * next_from_previous.rotation * rig.left.K().inverse();
  maps.right = rig.right.K() * right_motion.rotation * rig.right.K().inverse();
  return maps;
}

bool MapSegment(const Eigen::Matrix3d& h, const Segment2d& segment, Segment2d* mapped) {
  for (int e = 0; e < 2; ++e) {
    const Eigen::Vector3d q = h * Homogeneous(segment.segment<2>(2 * e));
    if (!(q.z() > 1e-12)) return false;
    mapped->segment<2>(2 * e) = q.head<2>() / q.z();
  }
  return mapped->allFinite();
}

}  // namespace slt
