#include "experiments/experiment_driver.h"

#include <chrono>
#include <filesystem>
#include <stdexcept>

#include "common/file_io.h"
#include "common/json_reader.h"
#include "common/source_tree.h"
#include "common/machine_info.h"

namespace slt {
namespace {

namespace fs = std::filesystem;

// Other runs' shard outputs under out_dir (and perhaps what is being merged): the swap that
// replaces out_dir carries them over.
constexpr const char* kShardsDir = "raw/shards";

void CheckOutputDir(const std::string& out_dir) {
  CheckReplaceableDirectory("--out", out_dir, "run.json", "run_experiment", kShardsDir);
}

// Writes raw/, config.resolved.json, the summaries (a whole run) and run.json last into `dir`,
// with `info` (what the run or the merge adds) and the version, machine and command line.
void WriteOutputs(const std::string& dir, const DriverOptions& options, const ExperimentConfig& config,
                  const std::vector<TrialResult>& trials, const nlohmann::json& resolved, const nlohmann::json& info,
                  std::chrono::steady_clock::time_point start) {
  CreateDirectories(dir);
  WriteRawResults(dir, config, trials);
  WriteJsonFile(JoinPath(dir, "config.resolved.json"), resolved);
  if (options.run.shard.IsWhole()) WriteSummaries(dir, config, trials);
  nlohmann::json run = VersionAndMachineJson(SourceDir());
  run["program"] = "run_experiment";
  run["command_line"] = options.command_line;
  run["config_file"] = options.config_file;
  run.update(info);
  run["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  WriteJsonFile(JoinPath(dir, "run.json"), run);
}

// The finished jobs of an earlier run of `resolved`, for --resume: the journal in the staging
// directory, else a finished run in out_dir; none when neither exists. Throws when what is
// there is a run of another config.
std::vector<TrialResult> CompletedJobs(const std::string& out_dir, const ExperimentConfig& config,
                                       const nlohmann::json& resolved) {
  std::error_code error;
  for (const std::string& dir : {StagingDir(out_dir), out_dir}) {
    const std::string config_path = JoinPath(dir, "config.resolved.json");
    if (!fs::exists(config_path, error)) continue;
    if (ReadJsonFile(config_path) != resolved) {
      throw std::runtime_error("--resume: " + config_path +
                               " is another config's (run without --resume to start afresh)");
    }
    if (!fs::exists(JoinPath(dir, "raw/trials.csv"), error)) continue;
    return ReadRawResults(dir, config);
  }
  return {};
}

}  // namespace

ExperimentRun RunAndWrite(const ExperimentConfig& config, const DriverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::string started = UtcNow();
  CheckOutputDir(options.out_dir);
  const nlohmann::json resolved = ResolvedConfigJson(config);  // fails early on bad tracker options
  RunOptions run_options = options.run;
  if (options.resume) run_options.completed = CompletedJobs(options.out_dir, config, resolved);
  const std::string staging = FreshStagingDir(options.out_dir);  // after the journal is read
  WriteJsonFile(JoinPath(staging, "config.resolved.json"), resolved);
  // The journal of finished jobs, rewritten at most every few seconds (each write is atomic, so
  // an interruption leaves the previous one); the reused jobs at once.
  std::vector<TrialResult> journal = run_options.completed;
  if (!journal.empty()) WriteRawResults(staging, config, journal);
  auto last_write = std::chrono::steady_clock::now();
  run_options.on_trial = [&](const TrialResult& trial) {
    journal.push_back(trial);
    if (std::chrono::steady_clock::now() - last_write < std::chrono::seconds(5)) return;
    WriteRawResults(staging, config, journal);
    last_write = std::chrono::steady_clock::now();
  };
  ExperimentRun run = RunExperiment(config, run_options);
  const Shard& shard = options.run.shard;
  WriteOutputs(staging, options, config, run.trials, resolved,
               {{"started_utc", started},
                {"threads", run.threads},
                {"jobs", {{"total", run.jobs_total}, {"run", run.trials.size()}}},
                {"shard", shard.IsWhole() ? nlohmann::json(nullptr)
                                          : nlohmann::json({{"index", shard.index}, {"count", shard.count}})},
                {"experiment_time_s", run.wall_time_s},
                {"resumed_jobs", run_options.completed.size()}},
               start);
  ReplaceDirectory(staging, options.out_dir, kShardsDir);
  return run;
}

MergedRun MergeAndWrite(const std::vector<std::string>& shard_dirs, const DriverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::string started = UtcNow();
  CheckOutputDir(options.out_dir);
  std::vector<std::pair<std::string, std::string>> shards;
  for (const std::string& dir : shard_dirs) shards.emplace_back("the shard", dir);
  RefusePathsInReplacedDirectory("--out", options.out_dir, shards, kShardsDir);
  MergedRun merged = MergeShardOutputs(shard_dirs);
  const std::string staging = FreshStagingDir(options.out_dir);
  double experiment_time = 0.0;  // the sum over the shards
  for (const nlohmann::json& shard : merged.shards) experiment_time += shard.value("experiment_time_s", 0.0);
  WriteOutputs(staging, options, merged.config, merged.trials, ResolvedConfigJson(merged.config),
               {{"started_utc", started},
                {"jobs", {{"total", merged.trials.size()}, {"merged", merged.trials.size()}}},
                {"shard", nullptr},
                {"merged_from", merged.shards},
                {"experiment_time_s", experiment_time}},
               start);
  ReplaceDirectory(staging, options.out_dir, kShardsDir);
  return merged;
}

void RunPlotScript(const std::string& dir, bool quiet) {
  std::vector<std::string> args = {dir};
  if (quiet) args.push_back("--quiet");
  try {
    RunPythonScript("scripts/plot_experiment.py", args);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string("plotting failed (") + e.what() +
                             "); the results are written, only the plots are missing (use --no-plots to skip them)");
  }
}

}  // namespace slt
