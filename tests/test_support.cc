#include "tests/test_support.h"

#include <algorithm>
#include <cmath>

#include "geometry/se3.h"

namespace slt {

TrackRun RunTracker(PoseTracker& tracker, const StereoSequence& sequence) {
  TrackRun run;
  for (const TrackedFrame& frame : TrackSequence(tracker, sequence)) run.outputs.push_back(frame.output);
  return run;
}

PoseError ErrorAt(const SimulatedSequence& sim, const TrackRun& run, int frame) {
  const Rigid3d& world_from_true = sim.ground_truth[frame].world_from_cam;
  const Rigid3d world_from_est = run.outputs[frame].cam_from_world.Inverse();
  PoseError e;
  e.rotation_deg = RotationAngle(world_from_true.rotation.transpose() * world_from_est.rotation) * 180.0 / M_PI;
  e.translation_m = (world_from_true.translation - world_from_est.translation).norm();
  return e;
}

TrialErrors FinalErrorOverTrials(const std::string& method, const nlohmann::json& tracker_options,
                                 const nlohmann::json& simulation, int trials, std::uint64_t first_seed) {
  TrialErrors out;
  for (int k = 0; k < trials; ++k) {
    SimulationConfig config = SimulationConfigFromJson(simulation, "test simulation");
    config.seed = first_seed + k;
    const SimulatedSequence sim = Simulate(config);
    auto tracker = CreateTracker(method, tracker_options, "test tracker options");
    const TrackRun run = RunTracker(*tracker, sim.sequence);
    for (const TrackerOutput& o : run.outputs) out.all_finite = out.all_finite && IsFinite(o.cam_from_world);
    const PoseError e = ErrorAt(sim, run, static_cast<int>(run.outputs.size()) - 1);
    out.mean.rotation_deg += e.rotation_deg / trials;
    out.mean.translation_m += e.translation_m / trials;
    // NaN-propagating maximum: std::max(worst, NaN) would keep `worst` and hide the trial.
    if (!(e.rotation_deg <= out.worst.rotation_deg)) out.worst.rotation_deg = e.rotation_deg;
    if (!(e.translation_m <= out.worst.translation_m)) out.worst.translation_m = e.translation_m;
  }
  return out;
}

StereoSequence KeepLines(const StereoSequence& sequence, const std::vector<std::int64_t>& ids) {
  return FilterLines(sequence, [&](std::int64_t id) { return std::find(ids.begin(), ids.end(), id) != ids.end(); });
}

std::vector<std::int64_t> WellConditionedLines(const SimulatedSequence& sim, int count) {
  std::vector<std::int64_t> ids;
  std::vector<Eigen::Vector3d> directions;
  for (size_t i = 0; i < sim.lines.size() && static_cast<int>(ids.size()) < count; ++i) {
    const Eigen::Vector3d d = (sim.lines[i].q - sim.lines[i].p).normalized();
    // At least 45 deg from the horizontal (epipolar) direction in the image, not along z.
    if (std::abs(d.y()) < 0.7 * d.head<2>().norm() || std::abs(d.z()) > 0.7) continue;
    bool distinct = true;
    for (const Eigen::Vector3d& other : directions) distinct = distinct && std::abs(d.dot(other)) < 0.94;
    if (!distinct) continue;
    ids.push_back(static_cast<std::int64_t>(i));
    directions.push_back(d);
  }
  return ids;
}

bool IsFinite(const Rigid3d& pose) { return pose.AllFinite(); }

}  // namespace slt
