// Runs an experiment: every (method, sweep point, trial) job on a pool of threads.
//
// Job j = (method * points + point) * trials + trial. Trial k of every point and method
// simulates with seed TrialSeed(config.seed, k), and each job creates its own tracker, so a
// job's result depends only on the config and j: identical for any thread count and order
// (except the wall-time columns).
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "experiments/experiment_config.h"
#include "experiments/trial_result.h"

namespace slt {

// The index of a job: (method * points + point) * trials + trial, with `points` sweep points.
inline size_t JobIndex(size_t points, int trials, size_t method, size_t point, int trial) {
  return (method * points + point) * static_cast<size_t>(trials) + static_cast<size_t>(trial);
}

struct Job {
  size_t index = 0;
  size_t method = 0;
  size_t point = 0;
  int trial = 0;
};

// Every job of the experiment, in index order.
std::vector<Job> ExperimentJobs(const ExperimentConfig& config);

// --shard i/n: the jobs whose index % n == i.
struct Shard {
  int index = 0;
  int count = 1;
  bool Contains(size_t job) const { return static_cast<int>(job % static_cast<size_t>(count)) == index; }
  bool IsWhole() const { return count == 1; }
};
// Parses "i/n" (0 <= i < n); throws std::invalid_argument.
Shard ParseShard(const std::string& text);

struct RunOptions {
  int threads = 0;  // 0 = CpuCores() (common/machine_info.h)
  Shard shard;
  // Called after each finished job with (done, total), from one thread at a time.
  std::function<void(size_t, size_t)> on_progress;
  // Called after each finished job with its result, from one thread at a time (the driver's
  // journal for --resume).
  std::function<void(const TrialResult&)> on_trial;
  // Jobs already run (--resume): not run again; their results are returned as given. Results
  // of jobs outside the shard are ignored.
  std::vector<TrialResult> completed;
};

struct ExperimentRun {
  std::vector<TrialResult> trials;  // the shard's jobs, in job order
  size_t jobs_total = 0;            // of the whole experiment
  int threads = 1;
  double wall_time_s = 0.0;
};

// Throws std::runtime_error naming the job (method, sweep point, trial, seed) when a trial
// fails; the other threads stop at their next job.
ExperimentRun RunExperiment(const ExperimentConfig& config, const RunOptions& options);

// "method 'x', noise.endpoint_px = 1, trial 3 (seed 123)".
std::string DescribeJob(const ExperimentConfig& config, const std::vector<SweepPoint>& points, const Job& job);

}  // namespace slt
