// Temporal tracking of line segments by pyramidal Lucas-Kanade optical flow (paper Sec. 3.1;
// Lucas & Kanade 1981, Bouguet's pyramidal form in cv::calcOpticalFlowPyrLK), one image stream
// at a time, in two stages the front end times separately:
//
//   Flow:  K points p_k = a + (k / (K-1)) (b - a) along each segment (K from the length and
//          options.point_spacing_px, within [min_points, max_points]) are tracked from the
//          previous image into the next one, all segments in one call;
//   Refit: per segment, a RANSAC line fit to the tracked points (optim/ransac.h; inliers within
//          inlier_px), refined by total least squares on the inliers; the new endpoints come
//          from a least-squares map t' = alpha t + beta between the points' positions along the
//          old segment (t) and along the new line (t'), applied to the old endpoints, so that an
//          endpoint whose own point was lost still moves with the segment. The segment keeps its
//          orientation and is clipped to the image. It is lost when fewer than
//          max(min_inlier_fraction K, 3) points are inliers, the inliers' RMS distance exceeds
//          max_rms_px, alpha leaves [0.5, 2] or the clipped segment is shorter than
//          min_length_px;
//   Snap:  (when options.snap_radius_px > 0) the refitted line is moved onto the image's edge:
//          at M places x_m along it, one every snap_spacing_px (at most snap_max_places, 3 px
//          clear of the endpoints), the gradient across the line
//          g_m(o) = grad I(x_m + o n) . n is searched for its strongest value of the line's
//          polarity (the sign of the mean g at |o| <= 1) over whole-pixel offsets
//          |o| <= ceil(snap_radius_px), on the Scharr derivatives the pyramid holds (so Flow()
//          takes pyramids made by BuildPyramid); the maximum, located to sub-pixel by a
//          parabola through its neighbours, is an edge point when it is at least
//          snap_min_gradient and not on the search's border. The line is refitted by total
//          least squares to the edge points (twice, dropping points over snap_inlier_px from it),
//          and the refitted endpoints are projected onto it. Lost when fewer than
//          max(3, snap_min_fraction M) edge points remain; a tracked line also when the standard error of the
//          fitted direction, sigma = rms / sqrt(sum_m (t_m - mean t)^2) over the K edge points
//          (rms = sqrt(sum_m r_m^2 / (K - 2)) of the residuals r across the line, positions t
//          along it), exceeds max_angle_sigma_deg. Frame-to-frame flow alone integrates
//          its errors (a track drifts off its edge by ~2 px over 20-100 frames, measured in
//          docs/frontend.md); the snap measures the line in the current image each frame.
//          The snap trims the segment to the extent of its edge but never lengthens it, so a
//          tracked segment's ends then grow back along the edge (ExtendAlongEdge, by at most
//          options.extend_max_px per frame): the extent follows the edge both ways.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "frontend/frontend_options.h"
#include "frontend/line_detection.h"
#include "geometry/line2d.h"
#include "optim/ransac.h"

namespace slt {

using ImagePyramid = std::vector<cv::Mat>;

// Why a tracked line was dropped (kKept: it was not). Refit gives the reasons of one image;
// the stereo front end adds kStereo for a pair that fails its stereo tests, and reports a line
// lost in either image by that image's reason (FrontEndFrameStats::lost_by, track_images' log
// and summary), so that where a sequence loses its lines is measured, not guessed.
enum class LineLoss : std::uint8_t {
  kKept,
  kFlowAtBorder,  // too few flow points kept (LK status), on a segment within window_px of the
                  // image's border: the line is leaving the view
  kFlowPoints,    // too few flow points kept, elsewhere
  kRefit,         // too few inliers to the refitted line, their RMS over max_rms_px, or the
                  // endpoint map's scale alpha outside [0.5, 2]
  kSnap,          // too few edge points of the line's polarity to snap to
  kDirection,     // the snapped line's direction undetermined (max_angle_sigma_deg)
  kShort,         // outside the image, or shorter than min_length_px once clipped to it
  kStereo,        // (the stereo front end) the pair's overlap along the epipolar lines or its
                  // disparity out of range
};
inline constexpr int kNumLineLosses = 8;
const char* LineLossName(LineLoss loss);  // "flow_at_border", ...

// The refit of one segment (stage 2 above, before clipping): lost for the reason `loss`
// (kFlowPoints, the default: nothing fitted yet; or kRefit), kept when kKept.
struct LineRefit {
  LineLoss loss = LineLoss::kFlowPoints;
  bool ok() const { return loss == LineLoss::kKept; }
  Segment2d segment = Segment2d::Zero();  // the new segment, oriented as the old one
  int inliers = 0;
  double rms_px = 0.0;  // RMS distance of the inliers to the fitted line
};
// `points` are the tracked positions of those of the `sampled` sample points of `old` that the
// flow kept, `positions` their distances from old's first endpoint along it.
LineRefit RefitTrackedLine(const TrackingOptions& options, const Segment2d& old, int sampled,
                           const std::vector<Eigen::Vector2d>& points, const std::vector<double>& positions,
                           Ransac<Eigen::Vector3d>* ransac, RansacResult<Eigen::Vector3d>* workspace);

// The snap above, in place: false when the segment is lost. `derivatives` is the level-0
// derivative image of an ImagePyramid (CV_16SC2, OpenCV's Scharr, 32 x the gradient);
// `workspace` is reused from call to call.
struct SnapWorkspace {
  std::vector<float> profiles;
  std::vector<Eigen::Vector2d> edge_points;
};
// With `direction_sigma_deg`, also the standard error of the fitted line's direction, deg
// (edge points' residual RMS over their spread along the line; infinite without spread), for
// the tracker's loss test below.
bool SnapSegmentToEdges(const TrackingOptions& options, const cv::Mat& derivatives, Segment2d* segment,
                        SnapWorkspace* workspace, double* direction_sigma_deg = nullptr);
// The tracker's direction test: a snapped line whose direction's standard error exceeds
// options.max_angle_sigma_deg (0 = off) is lost.
inline bool DirectionUndetermined(const TrackingOptions& options, double direction_sigma_deg) {
  return options.max_angle_sigma_deg > 0.0 && direction_sigma_deg > options.max_angle_sigma_deg;
}

// The snap's counterpart (the snap only trims an end the flow carried past the edge's end): each
// end of a snapped segment grows outwards along the segment's line while the line lies on its
// edge. The place x = end - margin + j s (j = 1, 2, ...; s = options.snap_spacing_px, margin the
// snap's 3-px end margin, i.e. the last place the snap could use) is on the edge when the
// gradient across the line there, of the segment's polarity, is at least
// max(options.snap_min_gradient, g / 2) and not below that 1 px to either side (the snap's
// trimming test, with the edge's own strength: g = the mean gradient across the segment at its
// quarter points, whose sign is the polarity); the end moves to the last such place + margin, by at most
// options.extend_max_px, staying in the image. The line itself does not change. Nothing when
// extend_max_px is 0.
void ExtendAlongEdge(const TrackingOptions& options, const cv::Mat& derivatives, Segment2d* segment);

// Detected segments moved onto the image's edges by the snap above (a coarse, fast detection
// made precise: DetectionOptions::snap_detections), in place; a segment the snap cannot place
// or leaves shorter than min_length_px is dropped (it would be lost at its first tracked
// frame). `derivatives` as above. With the snap off (snap_radius_px 0) nothing changes.
void SnapDetections(const TrackingOptions& options, double min_length_px, const cv::Mat& derivatives,
                    std::vector<ImageLine>* lines, SnapWorkspace* workspace);

class LineFlowTracker {
 public:
  explicit LineFlowTracker(const TrackingOptions& options, std::uint64_t seed = 1);

  // The pyramid (with derivatives) that Flow() takes, built once per image, with
  // options.pyramid_levels levels above the image, or `levels` when more.
  void BuildPyramid(const cv::Mat& grey, ImagePyramid* pyramid, int levels = 0) const;
  // Stage 1: tracks the sample points of `segments` from `previous` into `next`.
  void Flow(const ImagePyramid& previous, const ImagePyramid& next, const std::vector<Segment2d>& segments);
  // The same, seeded (large motion, issue 19): each point p of segment i starts its search at
  // H_i p (homogeneous; `point_maps[i]` = H_i, a homography from the previous image to the next
  // one, e.g. the motion a predicted camera motion gives to the segment's 3-D line) instead of
  // at p, and the search uses the pyramid's levels 0 .. `levels` (at most those built). A seed
  // that is not finite or falls outside the image starts at p.
  void Flow(const ImagePyramid& previous, const ImagePyramid& next, const std::vector<Segment2d>& segments,
            const std::vector<Eigen::Matrix3d>& point_maps, int levels);
  // Stage 2: the refitted (and snapped) segments (losses[i] = why segment i is lost, kKept when
  // it is not), for the segments of the last Flow() call, in an image of the given size.
  void Refit(int width, int height, std::vector<Segment2d>* tracked, std::vector<LineLoss>* losses);

  // The mean RMS refit residual of the segments kept by the last Refit, px (diagnostics).
  double last_mean_rms() const { return last_mean_rms_; }

 private:
  TrackingOptions options_;
  Ransac<Eigen::Vector3d> ransac_;
  RansacResult<Eigen::Vector3d> result_;
  std::vector<Segment2d> segments_;
  cv::Mat derivatives_;  // of the last Flow()'s next image
  std::vector<int> first_point_;  // per segment, index of its first point; size n + 1
  std::vector<cv::Point2f> points_, tracked_points_;
  std::vector<uchar> status_;
  std::vector<float> error_;
  std::vector<Eigen::Vector2d> data_;
  std::vector<double> positions_;
  SnapWorkspace snap_;
  double last_mean_rms_ = 0.0;

  // Samples the points of `segments` into points_ and first_point_.
  void SamplePoints(const std::vector<Segment2d>& segments);
  void RunLucasKanade(const ImagePyramid& previous, const ImagePyramid& next, int levels, int flags);
};

}  // namespace slt
