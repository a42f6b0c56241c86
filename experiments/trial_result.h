// What one trial (a method on one simulated sequence) produces, and the names of its metrics
// as they appear in the CSV files. docs/experiments.md defines every metric.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dataset/trajectory.h"
#include "evaluation/metrics.h"

namespace slt {

// Per-trial metrics, declared once: X(enumerator, CSV column, title in tables and plots), in
// CSV column order. docs/experiments.md defines each; errors are the ATE terms with alignment
// "none". The reason columns count frames by TrackerOutput::reason (methods/pose_tracker.h).
#define SLT_TRIAL_METRICS(X)                                                                               \
  X(kRotErrDeg, "rot_err_deg", "Rotation error (deg)") /* at the metrics frame: the paper's value */       \
  X(kTransErrM, "trans_err_m", "Translation error (m)")                                                    \
  X(kFinalRotErrDeg, "final_rot_err_deg", "Final rotation error (deg)")                                    \
  X(kFinalTransErrM, "final_trans_err_m", "Final translation error (m)")                                   \
  X(kAteTransM, "ate_trans_m", "ATE translation RMSE (m)")                                                 \
  X(kAteRotDeg, "ate_rot_deg", "ATE rotation RMSE (deg)")                                                  \
  X(kMaxTransErrM, "max_trans_err_m", "Largest translation error (m)")                                     \
  X(kMaxRotErrDeg, "max_rot_err_deg", "Largest rotation error (deg)")                                      \
  X(kRpeTransM, "rpe_trans_m", "RPE translation RMSE (m)")                                                 \
  X(kRpeRotDeg, "rpe_rot_deg", "RPE rotation RMSE (deg)")                                                  \
  X(kPathLengthM, "path_length_m", "Path length (m)")                                                      \
  X(kEndGapM, "end_gap_m", "Start-to-end gap (m)")                                                         \
  X(kDriftPct, "drift_pct", "Gap / path length (%)")                                                       \
  X(kTimeMeanUs, "time_mean_us", "Time per frame (us)")                                                    \
  X(kTimeMedianUs, "time_median_us", "Median time per frame (us)")                                         \
  X(kFeaturesUsed, "features_used", "Features used per frame")                                             \
  X(kFeaturesAvailable, "features_available", "Features available per frame")                              \
  X(kNewReferences, "new_references", "New reference pairs")                                               \
  X(kLostFrames, "lost_frames", "Lost frames")                                                             \
  X(kNewRefFewFeatures, "new_ref_few_features", "New reference pairs: fewer than min_features left")       \
  X(kNewRefFeatureFraction, "new_ref_feature_fraction", "New reference pairs: below min_feature_fraction") \
  X(kLostFewMeasurable, "lost_few_measurable", "Lost frames: too few measurable features")                 \
  X(kLostFewInsideGate, "lost_few_inside_gate", "Lost frames: too few features inside the gate")           \
  X(kLostNoUpdate, "lost_no_update", "Lost frames: no update solution")                                    \
  X(kLostNonFinite, "lost_non_finite", "Lost frames: non-finite state")                                    \
  X(kLostUnconstrained, "lost_unconstrained", "Lost frames: a pose direction not measured")                \
  X(kLostFewAgree, "lost_few_agree", "Lost frames: under a quarter of the features agree")                 \
  X(kFeaturesUnmatched, "features_unmatched", "Reference features not matched in both images, per frame")  \
  X(kFeaturesDegenerate, "features_degenerate", "Degenerate features per frame")                           \
  X(kFeaturesOutsideGate, "features_outside_gate", "Measurable features outside the gate, per frame")      \
  X(kDegradedFrames, "degraded_frames", "Degraded frames")                                                 \
  X(kNees, "nees", "NEES (6 dof, mean)")                                                                   \
  X(kNeesRot, "nees_rot", "NEES orientation (3 dof)")                                                      \
  X(kNeesPos, "nees_pos", "NEES position (3 dof)")                                                         \
  X(kBeyond3SigmaPct, "beyond_3sigma_pct", "Errors beyond 3 sigma (%)")

enum TrialMetric {
#define SLT_METRIC_ENUMERATOR(id, name, title) id,
  SLT_TRIAL_METRICS(SLT_METRIC_ENUMERATOR)
#undef SLT_METRIC_ENUMERATOR
  kNumTrialMetrics
};

// The CSV column of a metric ("unknown" out of range); -1 for an unknown name.
const char* TrialMetricName(int metric);
int TrialMetricFromName(const std::string& name);

struct TrialResult {
  size_t method_index = 0;  // into ExperimentConfig::methods
  size_t point_index = 0;   // into ExpandSweep(config.sweep)
  int trial = 0;
  std::uint64_t seed = 0;   // the simulation seed
  int frames = 0;
  int metrics_frame = 0;
  bool finite = true;       // every estimated pose was finite (otherwise the errors are NaN)
  std::array<double, kNumTrialMetrics> metrics{};
  ErrorCurve curve;         // per-frame errors, when the config asks for curves
  // When the config saves this trial's trajectories: world_from_cam per frame.
  Trajectory ground_truth;
  Trajectory estimate;
};

}  // namespace slt
