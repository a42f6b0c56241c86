#include "experiments/experiment_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>

#include "common/csv.h"
#include "common/machine_info.h"
#include "common/parallel.h"
#include "common/random.h"
#include "evaluation/consistency.h"
#include "evaluation/statistics.h"
#include "frontend/frontend_options.h"
#include "frontend/image_sequence.h"
#include "frontend/image_tracking.h"
#include "methods/pose_tracker.h"
#include "simulator/simulator.h"

namespace slt {
namespace {

// The metrics of one run from its per-frame tracker outputs (with each frame's time and the wall
// time of its Track() call) against the ground truth (empty: only the run's own metrics).
void FillMetrics(const ExperimentConfig& config, const Trajectory& ground_truth, const std::vector<TrackedFrame>& run,
                 TrialResult* r) {
  r->frames = static_cast<int>(run.size());
  r->metrics_frame = MetricsFrameFor(config, r->frames);
  Trajectory estimate;
  estimate.reserve(run.size());
  std::vector<double> times_us;
  times_us.reserve(run.size());
  RunCounts counts;
  std::vector<Matrix6d> covariances;
  bool has_covariance = true;
  for (size_t k = 0; k < run.size(); ++k) {
    const TrackerOutput& out = run[k].output;
    times_us.push_back(run[k].time_us);
    counts.Add(out);
    has_covariance = has_covariance && out.has_covariance;
    covariances.push_back(out.covariance);
    r->finite = r->finite && out.cam_from_world.AllFinite();
    estimate.push_back({run[k].frame_time, out.cam_from_world.Inverse()});
  }

  auto& m = r->metrics;
  m.fill(std::numeric_limits<double>::quiet_NaN());
  const double n = std::max<double>(1.0, static_cast<double>(run.size()));
  const Summary times = Summarize(times_us);
  m[kTimeMeanUs] = times.mean;
  m[kTimeMedianUs] = times.median;
  m[kFeaturesUsed] = counts.features_used / n;
  m[kFeaturesAvailable] = counts.features_available / n;
  // The first frame's new reference defines the world: not a new reference pair.
  const bool first_is_new = !run.empty() && run.front().output.status == TrackingStatus::kNewReference;
  m[kNewReferences] = counts.Frames(TrackingStatus::kNewReference) - (first_is_new ? 1 : 0);
  m[kLostFrames] = counts.Frames(TrackingStatus::kLost);
  m[kNewRefFewFeatures] = counts.Frames(StatusReason::kFewFeaturesLeft);
  m[kNewRefFeatureFraction] = counts.Frames(StatusReason::kFeatureFractionLeft);
  m[kLostFewMeasurable] = counts.Frames(StatusReason::kFewMeasurable);
  m[kLostFewInsideGate] = counts.Frames(StatusReason::kFewInsideGate);
  m[kLostNoUpdate] = counts.Frames(StatusReason::kNoUpdate);
  m[kLostNonFinite] = counts.Frames(StatusReason::kNonFinite);
  m[kLostUnconstrained] = counts.Frames(StatusReason::kUnconstrained);
  m[kLostFewAgree] = counts.Frames(StatusReason::kFewAgree);
  m[kFeaturesUnmatched] = counts.features_unmatched / n;
  m[kFeaturesDegenerate] = counts.features_degenerate / n;
  m[kFeaturesOutsideGate] = counts.features_outside_gate / n;
  m[kDegradedFrames] = counts.Frames(TrackingStatus::kDegraded);
  if (!ground_truth.empty()) m[kPathLengthM] = PathLengthM(ground_truth);
  if (r->finite && !estimate.empty() && !ground_truth.empty()) {
    EvaluationOptions options;  // alignment none: both worlds are the first left camera
    const TrajectoryErrors errors = EvaluateTrajectory(ground_truth, estimate, options);
    // Recorded ground truth has its own rate (EuRoC: 200 Hz): there the last frame.
    const FrameError& at = config.datasets.empty() ? ErrorAtFrame(errors.per_frame, r->metrics_frame) : errors.Final();
    m[kRotErrDeg] = at.rot_err_deg;
    m[kTransErrM] = at.trans_err_m;
    m[kFinalRotErrDeg] = errors.Final().rot_err_deg;
    m[kFinalTransErrM] = errors.Final().trans_err_m;
    m[kAteTransM] = errors.ate_trans_m.rmse;
    m[kAteRotDeg] = errors.ate_rot_deg.rmse;
    m[kMaxTransErrM] = errors.ate_trans_m.max;
    m[kMaxRotErrDeg] = errors.ate_rot_deg.max;
    if (errors.rpe_trans_m.count > 0) {
      m[kRpeTransM] = errors.rpe_trans_m.rmse;
      m[kRpeRotDeg] = errors.rpe_rot_deg.rmse;
    }
    if (config.per_frame_curves) r->curve = errors.per_frame;
    if (has_covariance) {
      // The first frame defines the world: its covariance is zero and it is skipped.
      const ConsistencyErrors consistency =
          EvaluateConsistency(ground_truth, estimate, covariances, options.max_time_diff_s);
      m[kNees] = consistency.nees.mean;
      m[kNeesRot] = consistency.nees_rot.mean;
      m[kNeesPos] = consistency.nees_pos.mean;
      m[kBeyond3SigmaPct] = 100.0 * consistency.beyond_3sigma_fraction;
    }
  }
  if (r->finite && !estimate.empty()) {
    m[kEndGapM] = (estimate.back().world_from_cam.translation - estimate.front().world_from_cam.translation).norm();
    if (m[kPathLengthM] > 0.0) m[kDriftPct] = 100.0 * m[kEndGapM] / m[kPathLengthM];
  }
  if (r->trial < config.save_trajectories) {
    r->ground_truth = ground_truth;
    r->estimate = std::move(estimate);
  }
}

// A recorded sequence: the image front end and the tracker frame by frame (ImageTracker), the
// ground truth of the frames run, re-expressed from the first of them.
void RunDatasetTrial(const ExperimentConfig& config, PoseTracker& tracker, const DatasetSpec& dataset, TrialResult* r) {
  const std::unique_ptr<StereoImageSource> source =
      OpenStereoImages(dataset.path, dataset.layout, dataset.ground_truth);
  const int first = std::min(dataset.first_frame, source->size() - 1);
  const int end = dataset.end_frame < 0 ? source->size() : std::min(dataset.end_frame, source->size());
  StereoFrontEnd front_end(FrontEndOptionsFromJson(config.frontend, config.name + ": frontend"), source->rig());
  ImageTracker image_tracker(front_end, tracker, source->rig());
  std::vector<TrackedFrame> run;
  for (int k = first; k < end; ++k) {
    const StereoImages images = source->Read(k);
    const ImageTrackingStep step = image_tracker.Step(images.left, images.right, images.time);
    run.push_back({step.output, 1e6 * step.tracker_seconds, images.time});
  }
  // The ground truth over the frames run (within the association window of their times).
  Trajectory ground_truth;
  const double slack = 0.01;
  for (const TimedPose& pose : GroundTruthFromStart(source->ground_truth(), source->Time(first))) {
    if (pose.time >= run.front().frame_time - slack && pose.time <= run.back().frame_time + slack) ground_truth.push_back(pose);
  }
  FillMetrics(config, ground_truth, run, r);
}

// One job: simulate (or read the dataset), run the tracker timing each Track() call, evaluate
// (alignment none). Keeps the per-frame curve when config.per_frame_curves and the trajectories
// when job.trial < config.save_trajectories.
TrialResult RunTrial(const ExperimentConfig& config, const std::vector<SweepPoint>& points, const Job& job) {
  const MethodSpec& method = config.methods[job.method];
  TrialResult r;
  r.method_index = job.method;
  r.point_index = job.point;
  r.trial = job.trial;
  const bool recorded = !config.datasets.empty();
  const std::unique_ptr<PoseTracker> tracker =
      CreateTracker(method.name, recorded ? MethodOptionsOn(method, config.datasets[job.point]) : method.options,
                    config.name + ": method '" + method.Id() + "' options");
  if (recorded) {
    RunDatasetTrial(config, *tracker, config.datasets[job.point], &r);
    return r;
  }
  const SimulationConfig sim_config = TrialSimulation(config, points[job.point], job.trial);
  const SimulatedSequence sim = Simulate(sim_config);
  r.seed = sim_config.seed;
  FillMetrics(config, sim.ground_truth, TrackSequence(*tracker, sim.sequence), &r);
  return r;
}

}  // namespace

std::vector<Job> ExperimentJobs(const ExperimentConfig& config) {
  const size_t points = ExpandSweep(config.sweep).size();
  std::vector<Job> jobs;
  for (size_t m = 0; m < config.methods.size(); ++m) {
    for (size_t p = 0; p < points; ++p) {
      for (int k = 0; k < config.trials; ++k) jobs.push_back({JobIndex(points, config.trials, m, p, k), m, p, k});
    }
  }
  return jobs;
}

Shard ParseShard(const std::string& text) {
  Shard shard;
  const size_t slash = text.find('/');
  try {
    shard.index = ParseInteger<int>(text.substr(0, slash));
    shard.count = ParseInteger<int>(slash == std::string::npos ? "" : text.substr(slash + 1));
  } catch (const std::invalid_argument&) {
    throw std::invalid_argument("--shard: expected i/n (e.g. 0/4), got '" + text + "'");
  }
  if (shard.count < 1 || shard.index < 0 || shard.index >= shard.count) {
    throw std::invalid_argument("--shard: need 0 <= i < n, got '" + text + "'");
  }
  return shard;
}

std::string DescribeJob(const ExperimentConfig& config, const std::vector<SweepPoint>& points, const Job& job) {
  std::string s = "method '" + config.methods[job.method].Id() + "'";
  if (!config.sweep.empty()) s += ", " + PointText(config, points[job.point]);
  s += ", trial " + std::to_string(job.trial) + " (simulation seed " +
       std::to_string(TrialSeed(config.seed, static_cast<std::uint64_t>(job.trial))) + ")";
  return s;
}

ExperimentRun RunExperiment(const ExperimentConfig& config, const RunOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<SweepPoint> points = ExpandSweep(config.sweep);
  const std::vector<Job> all_jobs = ExperimentJobs(config);
  std::vector<const TrialResult*> completed(all_jobs.size(), nullptr);  // --resume
  for (const TrialResult& t : options.completed) {
    const size_t index = JobIndex(points.size(), config.trials, t.method_index, t.point_index, t.trial);
    if (index < completed.size()) completed[index] = &t;
  }
  // The shard's jobs; those completed are filled in, the others (to_run) are run.
  ExperimentRun run;
  run.jobs_total = all_jobs.size();
  std::vector<Job> jobs;
  std::vector<size_t> to_run;
  for (const Job& job : all_jobs) {
    if (!options.shard.Contains(job.index)) continue;
    if (completed[job.index] == nullptr) to_run.push_back(jobs.size());
    run.trials.push_back(completed[job.index] != nullptr ? *completed[job.index] : TrialResult());
    jobs.push_back(job);
  }
  const int threads = options.threads > 0 ? options.threads : CpuCores();
  run.threads = std::max(1, std::min<int>(threads, static_cast<int>(std::max<size_t>(1, to_run.size()))));
  std::mutex mutex;  // guards done and the callbacks
  size_t done = jobs.size() - to_run.size();
  ParallelFor(to_run.size(), run.threads, [&](size_t n) {
    const size_t i = to_run[n];
    try {
      run.trials[i] = RunTrial(config, points, jobs[i]);
    } catch (const std::exception& e) {
      throw std::runtime_error(DescribeJob(config, points, jobs[i]) + ": " + e.what());
    }
    const std::lock_guard<std::mutex> lock(mutex);
    ++done;
    if (options.on_trial) options.on_trial(run.trials[i]);
    if (options.on_progress) options.on_progress(done, jobs.size());
  });
  run.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

}  // namespace slt
