// Options of the Taylor & Kriegman baseline (taylor_line_sfm.h): the window, the segment cost,
// line initialisation, outliers and the Ceres solver. Every field has a default; its JSON key,
// range and one-line doc are declared once, in TaylorLineSfmOptionsSchema() (common/options.h).
#pragma once

#include <string>

#include "common/options.h"
#include "methods/pose_tracker.h"

namespace slt {

enum class SegmentLoss { kNone, kHuber, kCauchy };
enum class WindowLinearSolver { kDenseSchur, kSparseSchur };

struct TaylorLineSfmOptions {
  // Sliding window: the last window_frames stereo frames (the current one included); 0 = every
  // frame since the start (the batch form, for short sequences: the cost grows with the frames).
  int window_frames = 5;
  // A line enters the window's problem when frames of the window observe it at least this
  // often (in either image); a line seen once fixes nothing but itself.
  int min_observation_frames = 2;

  // Segment cost (taylor_segment_cost.h). sigma_px: the expected rms distance of a segment to
  // its line (px), so that costs are in standard deviations; length_weighting: Taylor's
  // integral (each segment weighs its length in pixels) or every segment once.
  double sigma_px = 1.5;
  bool length_weighting = true;
  // Robust loss on (rms / sigma)^2 with scale loss_scale (in sigma). Cauchy's influence falls
  // off for far segments: with 20 % outliers the paper protocol's error at frame 100 is about
  // half Huber's (docs/baselines.md).
  SegmentLoss loss = SegmentLoss::kCauchy;
  double loss_scale = 3.0;
  // After a solve, segments whose rms distance to their line exceeds this many sigma_px are
  // rejected for good and the window solved once more (0 = never).
  double outlier_rms_sigma = 5.0;

  // Stereo triangulation of a new line (geometry/plucker.h StereoPairLine) is degenerate when
  // the two back-projected planes meet at less than this angle (a line near the epipolar
  // plane, or a line far away: the angle is at most about baseline / depth); such a line is
  // left out and counted, and tried again on its next stereo frame. 0.5 deg at the paper
  // protocol's 0.5 m depth and 0.1 m baseline is a line within about 3 deg of its epipolar
  // line in the image, the trifocal-line EKF's min_epipolar_angle_deg.
  double min_plane_angle_deg = 0.5;

  // Ceres: linear solver (lines eliminated first), Levenberg-Marquardt iterations and
  // tolerances (ceres::Solver::Options), threads (1: deterministic, and the experiment runner
  // parallelises over trials instead).
  WindowLinearSolver linear_solver = WindowLinearSolver::kDenseSchur;
  int max_iterations = 10;
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
  int threads = 1;

  // A frame without a usable solve (status lost): the trackers' common policy.
  LostFrameOptions lost;

  // Throws ConfigError "<where>: key '<path>.<field>': ...".
  void Check(const std::string& where = "taylor_line_sfm options", const std::string& path = "") const;
};

const OptionSchema<TaylorLineSfmOptions>& TaylorLineSfmOptionsSchema();

}  // namespace slt
