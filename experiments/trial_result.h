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

// Per-trial metrics, in CSV column order. Errors are the ATE terms with alignment "none".
enum TrialMetric {
  kRotErrDeg,          // rotation error at the metrics frame (the paper's accumulated error)
  kTransErrM,          // translation error at the metrics frame
  kFinalRotErrDeg,     // at the last frame
  kFinalTransErrM,
  kAteTransM,          // ATE RMSE over all frames
  kAteRotDeg,
  kRpeTransM,          // RPE RMSE, delta = 1 frame
  kRpeRotDeg,
  kPathLengthM,        // length of the ground-truth path
  kEndGapM,            // distance between the estimated first and last camera centres
  kDriftPct,           // 100 * end_gap_m / path_length_m (closed loops: the paper's drift)
  kTimeMeanUs,         // mean wall time of one Track() call
  kTimeMedianUs,       // median wall time of one Track() call
  kFeaturesUsed,       // mean over frames of TrackerOutput::features_used
  kFeaturesAvailable,  // mean over frames of TrackerOutput::features_available
  kNewReferences,       // frames after the first with status kNewReference (new reference pairs)
  kLostFrames,         // frames with status kLost
  kNumTrialMetrics
};

const char* TrialMetricName(int metric);
// -1 when unknown.
int TrialMetricFromName(const std::string& name);
// True for the columns that measure time (they differ from run to run).
inline bool IsTimingMetric(int metric) { return metric == kTimeMeanUs || metric == kTimeMedianUs; }

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
