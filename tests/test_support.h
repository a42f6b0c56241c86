// Helpers shared by the cross-module tests: run a tracker over a simulated sequence and measure
// its pose errors against the ground truth.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "methods/pose_tracker.h"
#include "simulator/simulator.h"

namespace slt {

struct TrackRun {
  std::vector<TrackerOutput> outputs;  // one per frame
};

TrackRun RunTracker(PoseTracker& tracker, const StereoSequence& sequence);

struct PoseError {
  double rotation_deg = 0.0;
  double translation_m = 0.0;  // distance between the estimated and true camera centres
};

// Error of the pose at `frame` (camera-to-world of the left camera against the ground truth).
PoseError ErrorAt(const SimulatedSequence& sim, const TrackRun& run, int frame);

// Mean and worst error at the last frame over `trials` seeds (seed = first_seed + k). A NaN
// error makes the mean and the worst NaN (and every bound on them fail).
struct TrialErrors {
  PoseError mean;
  PoseError worst;
  bool all_finite = true;
};
TrialErrors FinalErrorOverTrials(const std::string& method, const nlohmann::json& tracker_options,
                                 const nlohmann::json& simulation, int trials, std::uint64_t first_seed = 1);

// The sequence restricted to the lines with the given ids.
StereoSequence KeepLines(const StereoSequence& sequence, const std::vector<std::int64_t>& ids);

// Ids of `count` lines of a simulated scene that a stereo rig along x sees well: far from the
// epipolar (horizontal) planes, not pointing at the camera, and not parallel to each other.
std::vector<std::int64_t> WellConditionedLines(const SimulatedSequence& sim, int count);

bool IsFinite(const Rigid3d& pose);

}  // namespace slt
