// Where a stereo-matched line moves in both images when the camera moves by a predicted
// next_from_previous (large motion, issue 19): the seeds of the optical flow
// (LineFlowTracker::Flow with point maps) and the gates of the re-matching (frame_matching.h).
//
// The 3-D line of a stereo pair (l, l') lies in both back-projected planes (paper Sec. 3.2:
// pi = [l; 0] of the left camera, pi' = E^T [l'; 0] of the right one). Every point X of the line
// on a plane n^T X + d = 0 (d != 0: the plane misses the camera's centre) moves as
//   X_next = R X + t = (R - t n^T / d) X,
// so in pixels the line's points move by the plane homography
//   H = K (R - t n^T / d) K^-1
// (Hartley & Zisserman, Multiple View Geometry, eq. 13.2). For the left image the plane is the
// right camera's pi' (which misses the left centre), for the right image the left camera's pi:
// each image's points are moved through the other camera's plane, exactly, whatever the
// points' positions along the line. A line near the epipolar plane (both planes nearly the
// same) has no depth: it gets no map.
#pragma once

#include <Eigen/Core>

#include "dataset/stereo_sequence.h"
#include "geometry/line2d.h"
#include "geometry/rigid3.h"

namespace slt {

// Pixel homographies from the previous images to the next ones, left and right.
struct StereoLineMaps {
  Eigen::Matrix3d left = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d right = Eigen::Matrix3d::Identity();
};

// The 3-D points of the pair's line at the left segment's endpoints (the left rays through them
// meet the right camera's plane pi'), in the left camera's frame. False when a ray misses the
// plane (a line near the epipolar plane) or a point is not in front of both cameras.
bool StereoSegmentEndpoints(const StereoRig& rig, const Segment2d& left, const Segment2d& right,
                            Eigen::Vector3d* first, Eigen::Vector3d* second);

// Back-projected planes closer than this (sine of their angle) are numerically one plane. Far
// lines have nearly coincident planes too, but there the depth matters little to the
// prediction; lines near the epipolar direction are excluded by the image angle instead.
constexpr double kMinStereoPlaneSine = 1e-6;

// The maps of the pair (left, right) (pixel segments of the rig's images) under the left
// camera's motion `next_from_previous`. False (maps unspecified) when the two back-projected
// planes meet at less than `min_plane_sine` (sine of the angle) or the line's points at the
// left segment's endpoints are not in front of both cameras.
// `depth`, when given, receives the mean depth of the line's points at the left endpoints.
bool PredictStereoLineMotion(const StereoRig& rig, const Rigid3d& next_from_previous, const Segment2d& left,
                             const Segment2d& right, double min_plane_sine, StereoLineMaps* maps,
                             double* depth = nullptr);

// The maps of a line on the fronto-parallel plane at `depth` (z = depth in the left camera): for
// lines the pair cannot place, at a typical depth of the scene.
StereoLineMaps FrontoParallelMaps(const StereoRig& rig, const Rigid3d& next_from_previous, double depth);

// The maps of a line at infinite depth, H = K R K^-1 (the rotation alone), per camera.
StereoLineMaps RotationOnlyMaps(const StereoRig& rig, const Rigid3d& next_from_previous);

// The pixel translation by `shift` as a homography.
inline Eigen::Matrix3d TranslationMap(const Eigen::Vector2d& shift) {
  Eigen::Matrix3d h = Eigen::Matrix3d::Identity();
  h.topRightCorner<2, 1>() = shift;
  return h;
}

// The segment with both endpoints mapped by the homography h (false when an endpoint goes to
// infinity or behind the camera).
bool MapSegment(const Eigen::Matrix3d& h, const Segment2d& segment, Segment2d* mapped);

}  // namespace slt
