#include "experiments/experiment_driver.h"

#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "common/json_reader.h"
#include "experiments/machine_info.h"

namespace slt {
namespace {

namespace fs = std::filesystem;

std::string Join(const std::string& dir, const std::string& file) { return (fs::path(dir) / file).string(); }


void MakeDirectory(const std::string& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw std::runtime_error(dir + ": cannot create directory (" + error.message() + ")");
}

// Writes raw/, config.resolved.json, the summaries (a whole run) and run.json last, with
// `info` (what the run or the merge adds) and the version, machine and command line.
void WriteOutputs(const DriverOptions& options, const ExperimentConfig& config, const std::vector<TrialResult>& trials,
                  const nlohmann::json& resolved, const nlohmann::json& info, std::chrono::steady_clock::time_point start) {
  MakeDirectory(options.out_dir);
  WriteRawResults(options.out_dir, config, trials);
  WriteJsonFile(Join(options.out_dir, "config.resolved.json"), resolved);
  if (options.run.shard.IsWhole()) WriteSummaries(options.out_dir, config, trials);
  nlohmann::json run = VersionAndMachineJson(SourceDir());
  run["program"] = "run_experiment";
  run["command_line"] = options.command_line;
  run["config_file"] = options.config_file;
  run.update(info);
  run["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  WriteJsonFile(Join(options.out_dir, "run.json"), run);
}

}  // namespace

ExperimentRun RunAndWrite(const ExperimentConfig& config, const DriverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::string started = UtcNow();
  MakeDirectory(options.out_dir);
  const nlohmann::json resolved = ResolvedConfigJson(config);  // fails early on bad tracker options
  ExperimentRun run = RunExperiment(config, options.run);
  const Shard& shard = options.run.shard;
  WriteOutputs(options, config, run.trials, resolved,
               {{"started_utc", started},
                {"threads", run.threads},
                {"jobs", {{"total", run.jobs_total}, {"run", run.trials.size()}}},
                {"shard", shard.IsWhole() ? nlohmann::json(nullptr)
                                          : nlohmann::json({{"index", shard.index}, {"count", shard.count}})},
                {"experiment_time_s", run.wall_time_s}},
               start);
  return run;
}

MergedRun MergeAndWrite(const std::vector<std::string>& shard_dirs, const DriverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::string started = UtcNow();
  MergedRun merged = MergeShardOutputs(shard_dirs);
  double experiment_time = 0.0;  // the sum over the shards
  for (const nlohmann::json& shard : merged.shards) experiment_time += shard.value("experiment_time_s", 0.0);
  WriteOutputs(options, merged.config, merged.trials, ResolvedConfigJson(merged.config),
               {{"started_utc", started},
                {"jobs", {{"total", merged.trials.size()}, {"merged", merged.trials.size()}}},
                {"shard", nullptr},
                {"merged_from", merged.shards},
                {"experiment_time_s", experiment_time}},
               start);
  return merged;
}

std::string DefaultOutputDir(const std::string& name) {
  std::error_code error;
  if (fs::is_directory(SourceDir(), error)) return Join(Join(SourceDir(), "results"), name);
  return Join("results", name);
}

std::string FindConfigFile(const std::string& name) {
  std::vector<std::string> candidates = {name};
  const bool has_suffix = name.size() > 5 && name.substr(name.size() - 5) == ".json";
  if (!has_suffix) candidates.push_back(name + ".json");
  for (const std::string& base : {std::string("experiments/configs"), Join(SourceDir(), "experiments/configs")}) {
    candidates.push_back(Join(base, name));
    if (!has_suffix) candidates.push_back(Join(base, name + ".json"));
  }
  std::error_code error;
  for (const std::string& c : candidates) {
    if (fs::is_regular_file(c, error)) return c;
  }
  std::string looked;
  for (const std::string& c : candidates) looked += (looked.empty() ? "" : ", ") + c;
  throw std::runtime_error("config '" + name + "' not found (looked for " + looked + ")");
}

void RunPlotScript(const std::string& dir, bool quiet) {
  std::string script = Join(SourceDir(), "scripts/plot_experiment.py");
  std::error_code error;
  if (!fs::is_regular_file(script, error)) script = "scripts/plot_experiment.py";
  if (!fs::is_regular_file(script, error)) {
    throw std::runtime_error("plotting: scripts/plot_experiment.py not found (results are written; use --no-plots)");
  }
  const char* env = std::getenv("SLT_PYTHON");
  const std::string python = env != nullptr && *env != '\0' ? env : "/usr/bin/python3";
  const std::string command = ShellQuote(python) + " " + ShellQuote(script) + " " + ShellQuote(dir) +
                              (quiet ? " --quiet" : "");
  const int status = std::system(command.c_str());
  if (status != 0) {
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : status;
    throw std::runtime_error("plotting failed (" + command + " exited with " + std::to_string(code) +
                             "); the results are written, only the plots are missing");
  }
}

}  // namespace slt
