// The image front end (paper Sec. 3.1): from stereo pictures to the tracked stereo line
// observations of the `stereo-lines/1` model, one frame at a time.
//
// Per stereo pair:
//   track   the live lines of the previous pair are followed into both images by optical flow
//           (line_tracking.h; one pyramid per image, kept for the next pair), each search
//           seeded where the predicted camera motion moves the line's 3-D line
//           (line_motion.h; the caller passes the tracker's prediction, image_tracking.h) or,
//           without one, where the line's last image motion moves it (options.motion);
//   filter  refit, loss tests, and stereo consistency: a line lost in one image is dropped in
//           both, and a pair whose segments leave each other's epipolar beam or the disparity
//           range is dropped;
//   rematch when the flow lost most lines (options.motion.rematch_below_fraction), the pair's
//           lines are detected, described and stereo-matched (the three stages below), and
//           each lost line is looked for among them by MSLD near its predicted position
//           (frame_matching.h): found, it keeps its id;
//   and, on the first pair and whenever the caller asks (the tracker wants new features:
//   PoseTracker::WantsNewFeatures, methods/pose_tracker.h):
//   detect   line segments in both images (line_detection.h),
//   describe MSLD descriptors (msld.h),
//   match    one-to-one stereo matches (stereo_matching.h); matched pairs that do not duplicate
//            a live line get new ids and join the live lines.
// With the temporal check on (matching.max_previous_px) and the tracker's measured motion of
// the last frames (image_tracking.h), the new lines are detected and matched in the *previous*
// pair, each candidate pair checked against the matching.previous_pairs pairs before it
// (its 3-D line moved there by the measured motions must lie on their edges: SeenInPreviousPair)
// before the uniqueness tests choose among those that pass, and the chosen ones are tracked
// into this pair with the live lines. The measured motion is an estimate after the tracker's
// update, several times closer to the truth than its prediction (docs/frontend.md), and a
// check over several pairs sees more parallax than one. Without a measured motion (the first
// pairs, after a lost frame) the matches of this pair are checked against the previous pair
// by the predicted motion.
// The output frame holds every live line under its id in both images (a stereo match), so the
// same id over frames is one tracked line. Memory does not grow with the sequence: only the
// live lines and the pyramids of the last pairs (two, and previous_pairs more with the check
// on) are kept.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <numeric>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "dataset/stereo_sequence.h"
#include "frontend/frame_matching.h"
#include "frontend/frontend_options.h"
#include "frontend/line_detection.h"
#include "frontend/line_tracking.h"
#include "frontend/msld.h"
#include "frontend/stereo_matching.h"
#include "geometry/rigid3.h"

namespace slt {

// Seconds spent per stage.
struct FrontEndStageTimes {
  double detect = 0.0, describe = 0.0, match = 0.0, track = 0.0, filter = 0.0;
  double Total() const { return detect + describe + match + track + filter; }
  FrontEndStageTimes& operator+=(const FrontEndStageTimes& o) {
    detect += o.detect;
    describe += o.describe;
    match += o.match;
    track += o.track;
    filter += o.filter;
    return *this;
  }
};

struct FrontEndFrameStats {
  bool detected = false;   // detection and matching ran (last_detections, last_matches) ...
  int detection_lag = 0;   // ... on the pair this many frames before this one (0 or 1)
  int tracked = 0;         // live lines carried over from the previous pair
  // Live lines of the previous pair dropped here, by reason (LineLoss; a line lost in either
  // image counts under that image's reason, the left one's first).
  std::array<int, kNumLineLosses> lost_by{};
  int lost() const { return std::accumulate(lost_by.begin(), lost_by.end(), 0); }
  int detected_left = 0;   // segments after merge, length and contrast filters
  int detected_right = 0;
  int matched = 0;         // stereo matches
  int added = 0;           // new live lines (matches that duplicate none)
  int predicted = 0;       // tracked lines whose flow was seeded by the predicted camera motion
  bool rematch = false;    // the flow lost most lines: re-matching ran on this pair
  int rematched = 0;       // lost lines found again by re-matching (in `live`, not in `tracked`)
  int live = 0;            // lines in the output frame
  FrontEndStageTimes times;
};

class StereoFrontEnd {
 public:
  StereoFrontEnd(const FrontEndOptions& options, const StereoRig& rig);

  // Processes the next stereo pair (8-bit grey, the rig's size). Detection runs when
  // `detect_new_lines` or on the first pair (and when re-matching). `predicted_motion`: the
  // left camera's motion from the previous pair to this one, next_from_previous, as the
  // tracker predicts it (none: no prediction). `measured_motion`: the left camera's motion
  // between the two pairs before this one, next_from_previous, as the tracker measured it
  // (none: not measured), for the temporal check of new lines (above). Throws
  // std::invalid_argument on a wrong image size or type.
  const StereoFrame& Process(const cv::Mat& left, const cv::Mat& right, double time, bool detect_new_lines,
                             const std::optional<Rigid3d>& predicted_motion = std::nullopt,
                             const std::optional<Rigid3d>& measured_motion = std::nullopt);

  const FrontEndFrameStats& last_stats() const { return stats_; }
  // The detections of the last pair where detection ran (for pictures and measurements).
  const std::vector<ImageLine>& last_detections(int camera) const { return detections_[camera]; }
  const std::vector<StereoMatch>& last_matches() const { return matches_; }
  const StereoMatcher& matcher() const { return matcher_; }
  const FrontEndOptions& options() const { return options_; }

 private:
  struct LiveLine {
    std::int64_t id;
    Segment2d left, right;
    // Midpoint motion in the last frame, per image (valid once tracked over one frame).
    Eigen::Vector2d shift[2] = {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
    bool has_shift = false;
  };
  // A live line the flow lost on this pair, with where it was predicted.
  struct LostLine {
    LiveLine line;
    Segment2d predicted[2];
    bool from_prediction;  // predicted from the camera motion (else from the image motion)
  };
  void Track(const std::optional<Rigid3d>& predicted_motion);
  using PyramidPair = std::array<ImagePyramid, 2>;
  // An earlier pair to check new matches against: its level-0 derivatives (left, right) and
  // the left camera's motion from the matched pair to it.
  struct EarlierPair {
    cv::Mat derivatives[2];
    Rigid3d from_matched;
  };
  // Detection, description and stereo matching of the images `left`, `right` (whose pyramids
  // are `pair`) into detections_, descriptors_, matches_; with matching.max_previous_px, the
  // pairs checked against the earlier pairs `checks`, before the uniqueness tests
  // (`assign_verified`) or after them.
  void DetectAndMatch(const cv::Mat& left, const cv::Mat& right, const PyramidPair& pair,
                      const std::vector<EarlierPair>& checks, bool assign_verified);
  // Looks for the lost lines among the matches.
  void Rematch();
  // New live lines from the matches that duplicate none.
  void AddNewLines();
  // Whether `segment`, in camera c (0 = left), lies on the segment of a live line there.
  bool DuplicatesLiveLine(const Segment2d& segment, int c = 0) const;

  FrontEndOptions options_;
  StereoRig rig_;
  std::unique_ptr<LineDetector> detector_;
  MsldExtractor msld_;
  StereoMatcher matcher_;
  LineFlowTracker flow_[2];
  PyramidPair previous_, current_;
  bool started_ = false;
  // The pairs before the previous one (earlier_[0] the latest), for checking new matches, and
  // the measured motion from each to the next later pair.
  std::vector<PyramidPair> earlier_;
  std::vector<std::optional<Rigid3d>> later_from_earlier_;
  int earlier_stored_ = 0;
  std::vector<EarlierPair> checks_;
  std::int64_t next_id_ = 0;
  std::vector<LiveLine> live_;
  StereoFrame frame_;
  FrontEndFrameStats stats_;
  // Workspace.
  std::vector<ImageLine> detections_[2];
  SnapWorkspace snap_;
  std::vector<MsldDescriptor> descriptors_[2];
  std::vector<StereoMatch> matches_;
  std::vector<Segment2d> segments_[2], tracked_[2];
  std::vector<LineLoss> losses_[2];
  std::vector<Eigen::Matrix3d> maps_[2];
  std::vector<char> from_prediction_;
  std::vector<int> unplaced_;  // lines with neither a camera nor an image seed
  std::vector<double> depths_;
  std::vector<LostLine> lost_;
  std::vector<FrameMatchQuery> queries_;
  std::vector<Segment2d> candidates_;
  std::vector<MsldDescriptor> candidate_descriptors_;
  std::vector<FrameMatch> frame_matches_;
};

}  // namespace slt
