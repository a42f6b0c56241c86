// Stereo matching of oriented line segments (paper Sec. 3.1): candidates satisfy the epipolar
// beam constraint, the MSLD descriptors (msld.h) decide, the photometric cross-correlation of
// the two segments confirms (> 0.6 in the paper), and matches are one-to-one.
//
// Epipolar beam. The paper states the constraint of Schmid & Zisserman as three determinant
// conditions on the endpoints x, y (left) and x', y' (right), the epipoles e, e' and F. Their
// signs depend on the signs chosen for the homogeneous e, e' and F, which the paper does not
// fix (with a rectified rig e = e' = (1, 0, 0) up to sign, and the first condition then reads
// "opposite vertical orientations", false for every correct match of oriented segments). We
// use the sign-free form of the same constraint: the epipolar lines F^T x' and F^T y' of the
// right endpoints cut the left segment's line at parameters t(x'), t(y'); the beams overlap
// when [t(x'), t(y')] meets the left segment. We ask for an overlap of at least min_overlap of
// the shorter of the two (in left pixels), a quantitative version of the overlap test for
// rectified rigs (where t is the row). Lines within epipolar_angle_deg of the epipolar
// direction lie (nearly) in an epipolar plane, where the beam degenerates: they are candidates
// when both right endpoints lie within epipolar_distance_px of the epipolar line of the left
// midpoint. A tracked pair (known to be one line) of such lines stays consistent by a test that
// admits a line a few degrees off the rows, which spans a few of them (kSameExtent below). With
// a rectified rig the disparity u_left - u_right must be in
// [min_disparity_px, max_disparity_px]; the two segments must point the same way.
//
// Cross-correlation: grey levels in a band of +-ncc_half_width_px across each segment, at
// corresponding points of the overlap (the left point and the intersection of its epipolar
// line with the right segment; for lines along the epipolar direction, the same fraction of
// each segment), compared by normalised cross-correlation.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <opencv2/core.hpp>
#include <vector>

#include "frontend/frontend_options.h"
#include "frontend/line_detection.h"
#include "frontend/line_tracking.h"
#include "frontend/msld.h"
#include "geometry/camera.h"
#include "geometry/rigid3.h"

namespace slt {

struct StereoMatch {
  int left = 0;   // index into the left lines
  int right = 0;  // index into the right lines
  float msld_distance = 0.0f;
  float ncc = 0.0f;
};

class StereoGeometry {
 public:
  explicit StereoGeometry(const StereoRig& rig);
  // x_right^T F x_left = 0 (pixels).
  const Eigen::Matrix3d& F() const { return f_; }
  bool rectified() const { return rectified_; }

  // Beam overlap (see above) of two segments as a fraction of the shorter (kShorter) or of the
  // union of the two extents (kUnion: 1 only when they cover the same part of the beam), in
  // [0, 1]. For a left segment within `epipolar_sine` of the epipolar direction, 1 or 0 by
  // `along`:
  //   kOnMidpointLine: both right endpoints within `epipolar_distance_px` of the epipolar line
  //     of the left midpoint (matching: a line spanning more than a few rows is no candidate);
  //   kSameExtent: the right segment within twice that angle of its own epipolar direction (the
  //     3-D line is near an epipolar plane, so both images are near epipolar lines) and, across
  //     the beam (s = the distance from the epipolar line of the left segment's first endpoint;
  //     the row in a rectified rig), the shorter of the two extents within the longer one
  //     widened by `epipolar_distance_px` each side (one end hidden in one image shortens
  //     that extent; `of` makes no difference here). For a tracked pair, whose lines turn
  //     across the 5-deg bound as the camera moves and span several rows at 4 deg over 70 px
  //     (docs/frontend.md, thirteenth pass).
  enum class OverlapOf { kShorter, kUnion };
  enum class AlongEpipolar { kOnMidpointLine, kSameExtent };
  double BeamOverlap(const Segment2d& left, const Segment2d& right, double epipolar_sine, double epipolar_distance_px,
                     OverlapOf of = OverlapOf::kShorter,
                     AlongEpipolar along = AlongEpipolar::kOnMidpointLine) const;
  // Whether the pair is in the disparity range at both ends of their common rows (always true
  // for a rig that is not rectified).
  bool DisparityInRange(const Segment2d& left, const Segment2d& right, double min_px, double max_px) const;
  // |sine| of the angle between the left segment and the epipolar line through its midpoint.
  double EpipolarSine(const Segment2d& left) const;
  // The point of the right segment's line corresponding to a left point (epipolar transfer),
  // or false when the right line is (nearly) an epipolar line.
  bool Transfer(const Eigen::Vector2d& left_point, const Segment2d& right, Eigen::Vector2d* right_point) const;

 private:
  Eigen::Matrix3d f_;
  Eigen::Vector3d left_epipole_;   // F e = 0
  Eigen::Vector3d right_epipole_;  // e'^T F = 0
  bool rectified_ = false;
};

// NCC of the bands along the overlapping parts of the two segments (see above); -1 when they
// have no overlap to compare.
double SegmentCrossCorrelation(const StereoGeometry& geometry, const cv::Mat& left_grey, const cv::Mat& right_grey,
                               const Segment2d& left, const Segment2d& right, bool along_epipolar, int half_width);

// Temporal verification of a stereo match (matching.max_previous_px): the pair's 3-D line,
// moved into the previous stereo pair by the camera motion `previous_from_current`
// (line_motion.h: each image's segment mapped by the plane homography of the other camera's
// back-projected plane), must lie on an edge there in both images: the edge snap
// (line_tracking.h, radius max_distance_px) finds it, and both mapped endpoints lie within
// max_distance_px of the snapped line. A pair of two different lines with common rows
// triangulates to a 3-D line at a wrong depth and direction, which the motion moves elsewhere
// than the true lines (paper scene, docs/frontend.md); the error of the motion (a tracker's
// prediction) must stay under the bound. `previous_derivatives`: the level-0 derivatives of
// the previous pair's pyramids (left, right). False also when the line cannot be placed (its
// points not in front of both cameras, or a line in an epipolar plane: no depth to move it by).
bool SeenInPreviousPair(const StereoRig& rig, const Rigid3d& previous_from_current, const Segment2d& left,
                        const Segment2d& right, const cv::Mat (&previous_derivatives)[2], const TrackingOptions& snap,
                        double max_distance_px, SnapWorkspace* workspace);

class StereoMatcher {
 public:
  StereoMatcher(const MatchingOptions& options, const StereoRig& rig);
  // One-to-one matches between the oriented lines of a stereo pair, described by MSLD
  // (descriptors[i] of lines[i]):
  // mutual nearest neighbours in MSLD distance passing the ratio test, then the union overlap
  // and the cross-correlation. With `verify` (a check of a pair by left and right index, e.g.
  // SeenInPreviousPair), every candidate is checked first (cross-correlation, `verify`; not the
  // union overlap, which the check makes redundant) and the uniqueness tests are among those
  // that pass: look-alike lines that the descriptor cannot tell apart, the check can.
  using PairCheck = std::function<bool(int left, int right)>;
  void Match(const cv::Mat& left_grey, const cv::Mat& right_grey, const std::vector<ImageLine>& left,
             const std::vector<MsldDescriptor>& left_descriptors, const std::vector<ImageLine>& right,
             const std::vector<MsldDescriptor>& right_descriptors, std::vector<StereoMatch>* matches,
             const PairCheck* verify = nullptr);
  const StereoGeometry& geometry() const { return geometry_; }

 private:
  MatchingOptions options_;
  StereoGeometry geometry_;
  double epipolar_sine_;
  // Workspace.
  struct Candidate {
    int left, right;
    float distance;
    float ncc;
  };
  std::vector<Candidate> candidates_;
  std::vector<float> best_left_, second_left_, best_right_, second_right_;
  std::vector<int> best_left_index_, best_right_index_, best_left_candidate_;
};

}  // namespace slt
