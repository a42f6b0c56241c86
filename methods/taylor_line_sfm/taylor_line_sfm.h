// The Taylor & Kriegman baseline (method name `taylor_line_sfm`): C.J. Taylor, D.J. Kriegman,
// "Structure and motion from line segments in multiple images", IEEE PAMI 17(11), 1995 -- 3-D
// lines and camera poses estimated together by non-linear least squares on the segments'
// integrated squared distance to the projected lines -- run as a stereo tracker over a sliding
// window, as the paper under study compares with it (Lee et al. 2015, Sec. 5.1, Table 1).
//
// Per stereo frame t:
//   1. prediction: T_t = Exp(xi) T_{t-1}, xi = Log(T_{t-1} T_{t-2}^-1) the last body-frame
//      increment (constant velocity; docs/conventions.md);
//   2. the frame joins the window of the last K frames (line_sfm_window.h), older frames and
//      lines no frame observes any more are dropped;
//   3. Ceres minimises Taylor's error (taylor_segment_cost.h) over the window's poses and lines,
//      the oldest pose held fixed; segments left far from their lines are rejected and the
//      window solved once more;
//   4. lines seen in both images for the first time are triangulated at the solved pose;
//   5. status: lost when the newest frame has fewer than two usable lines (lines of the problem
//      it observes), fewer than three segments of them, or the solve failed (a Ceres failure or
//      a non-finite solution): the pose is then the prediction with the velocity damped by
//      lost_velocity_decay, never a non-finite value. A solved frame is judged by every map
//      line it sees, those too new for the solve included: a line agrees when its segments
//      there lie within outlier_rms_sigma of it at the solved pose. Under a quarter agreeing
//      (pose_tracker.h FewAgree) the frame is lost (few_agree), under half degraded; the
//      solved pose stands either way.
//
// Options (JSON): TaylorLineSfmOptions (taylor_line_sfm_options.h), flat.
#pragma once

#include "methods/pose_tracker.h"
#include "methods/taylor_line_sfm/line_sfm_window.h"
#include "methods/taylor_line_sfm/taylor_line_sfm_options.h"

namespace slt {

class TaylorLineSfmTracker final : public PoseTracker {
 public:
  explicit TaylorLineSfmTracker(const TaylorLineSfmOptions& options);

  void Reset(const StereoRig& rig) override;
  TrackerOutput Track(const StereoFrame& frame) override;
  nlohmann::json Options() const override { return TaylorLineSfmOptionsSchema().ToJson(options_); }

  // Counters since Reset, for tests and diagnostics.
  struct Counters {
    int frames = 0;
    int lost_frames = 0;      // no usable solve, or under a quarter of the lines agree with it
    int degraded_frames = 0;  // solved, but under half of the lines the frame sees agree
    int solved_frames = 0;    // frames whose window was solved (the newest frame took part)
    int solves = 0;           // Ceres runs (two on a frame where outliers were rejected)
    int solve_failures = 0;   // frames whose solution was not usable (kept the previous state)
    int iterations = 0;       // Levenberg-Marquardt steps over all runs
    int rejected_observations = 0;  // segments rejected as outliers
    int dropped_lines = 0;          // lines dropped with them
    int lines_triangulated = 0;
    int degenerate_triangulations = 0;  // stereo pairs left out (near an epipolar plane)
    // Sum over frames of the lines the frame observed that were left out of its solve for too
    // few observations in the window.
    int lines_too_few_observations = 0;
  };
  const Counters& counters() const { return counters_; }
  const WindowSolveReport& last_solve() const { return last_solve_; }
  const LineSfmWindow& window() const { return window_; }

 private:
  TaylorLineSfmOptions options_;
  LineSfmWindow window_;
  bool started_ = false;
  Vector6d velocity_ = Vector6d::Zero();  // Log(T_t T_{t-1}^-1)
  // Lines of the map at the last tracked frame: those the current frame does not see in both
  // images are reported as TrackerOutput::features_unmatched (kept while lost).
  int known_lines_ = 0;
  Counters counters_;
  WindowSolveReport last_solve_;
  std::vector<LineObservation> sorted_;  // scratch of CollectWindowObservations
};

TrackerInfo TaylorLineSfmInfo();

}  // namespace slt
