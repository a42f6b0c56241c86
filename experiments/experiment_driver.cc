#include "experiments/experiment_driver.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <stdexcept>

#include "common/file_io.h"
#include "common/json_reader.h"
#include "common/script_runner.h"
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
  const std::string staging = StagingDir(options.out_dir);
  RunOptions run_options = options.run;
  if (options.resume) run_options.completed = CompletedJobs(options.out_dir, config, resolved);
  std::error_code error;
  fs::remove_all(staging, error);
  CreateDirectories(staging);
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
  const fs::path out = fs::weakly_canonical(fs::absolute(options.out_dir));
  for (const std::string& dir : shard_dirs) {
    // The swap replaces out_dir and keeps only its raw/shards/: a shard anywhere else in it
    // (or out_dir itself) would be lost.
    const fs::path shard = fs::weakly_canonical(fs::absolute(dir));
    const auto inside = [](const fs::path& path, const fs::path& root) {
      const fs::path relative = path.lexically_relative(root);
      return !relative.empty() && *relative.begin() != "..";
    };
    if (inside(shard, out) && !inside(shard, out / kShardsDir)) {
      throw std::runtime_error("--out " + options.out_dir + ": holds the shard " + dir +
                               " outside raw/shards/; the new results would replace it");
    }
  }
  MergedRun merged = MergeShardOutputs(shard_dirs);
  const std::string staging = StagingDir(options.out_dir);
  std::error_code error;
  fs::remove_all(staging, error);
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

std::string DefaultOutputDir(const std::string& name) {
  std::error_code error;
  if (fs::is_directory(SourceDir(), error)) return JoinPath(JoinPath(SourceDir(), "results"), name);
  return JoinPath("results", name);
}

std::string FindConfigFile(const std::string& name) {
  const bool has_suffix = name.size() > 5 && name.substr(name.size() - 5) == ".json";
  std::string looked, available;
  const std::string configs = "experiments/configs";
  for (const std::string& base : {std::string(), configs, JoinPath(SourceDir(), configs)}) {
    for (const std::string& file : {name, name + ".json"}) {
      if (has_suffix && file != name) continue;
      const std::string path = base.empty() ? file : JoinPath(base, file);
      std::error_code error;
      if (fs::is_regular_file(path, error)) return path;
      looked += (looked.empty() ? "" : ", ") + path;
    }
  }
  for (const std::string& c : AvailableConfigs()) available += (available.empty() ? "" : ", ") + c;
  throw std::runtime_error("config '" + name + "' not found (looked for " + looked + "); available: " +
                           (available.empty() ? "none found" : available));
}

std::vector<std::string> AvailableConfigs() {
  const fs::path root = fs::path(SourceDir()) / "experiments/configs";
  std::vector<std::string> names;
  std::error_code error;
  for (fs::recursive_directory_iterator it(root, error), end; !error && it != end; it.increment(error)) {
    if (it->is_regular_file(error) && it->path().extension() == ".json") {
      names.push_back(it->path().lexically_relative(root).replace_extension().generic_string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
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
