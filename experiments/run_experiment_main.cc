// run_experiment: runs an experiment config (docs/experiments.md) and writes its raw rows,
// summaries and plots.
//
//   run_experiment CONFIG [--out DIR] [--threads N] [--trials N] [--shard i/n] [--resume] [--no-plots] [--quiet]
//   run_experiment --merge DIR... [--out DIR] [--no-plots] [--quiet]
//
// CONFIG is a path, or a bare name found in experiments/configs/ ("noise_sweep",
// "noise_sweep.json", "ci/noise_sweep_ci"). Errors: one line "run_experiment: error: ..." on
// stderr, exit 1 (2 for command-line errors).

#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "common/command_line.h"
#include "common/file_io.h"
#include "common/json_reader.h"
#include "common/progress_bar.h"
#include "common/table.h"
#include "experiments/experiment_driver.h"
#include "experiments/regression.h"

namespace {

// The expected orderings and bounds (config "expect_better", "expect_bounds"): a note on stderr
// when one does not hold. Not an error: experiments_regression_test is the check.
void ReportExpectation(const slt::ExperimentConfig& config, const std::vector<slt::TrialResult>& trials) {
  const slt::RegressionReport report = slt::CheckExpectations(config, slt::SummarizeTrials(config, trials));
  for (const std::string& f : report.failures) std::fprintf(stderr, "run_experiment: note: %s\n", f.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  using namespace slt;
  CLI::App app{"Run an experiment: every (method, sweep point, trial) of a config; write raw rows, summaries, plots."};
  std::string config_arg, out_dir, shard_text;
  int threads = 0, trials = 0;
  std::vector<std::string> merge_dirs;
  bool no_plots = false, quiet = false, resume = false;
  app.add_option("config", config_arg, "Experiment config: a path or a name in experiments/configs/");
  app.add_option("--out,-o", out_dir, "Output directory (default results/<name>)");
  app.add_option("--threads", threads, "Worker threads (default: all cores)")->check(CLI::Range(0, 4096));
  app.add_option("--trials", trials, "Override the config's number of trials")->check(CLI::Range(1, 1000000));
  app.add_option("--shard", shard_text, "Run only the jobs with index % n == i (i/n); merge with --merge");
  app.add_option("--merge", merge_dirs, "Combine these shard output directories into one result");
  app.add_flag("--resume", resume,
               "Reuse the finished jobs of an interrupted (or earlier) run of the same resolved config in --out");
  app.add_flag("--no-plots", no_plots, "Do not draw the PNG plots");
  app.add_flag("--quiet,-q", quiet, "No progress bar, no final message");
  std::string configs;
  for (const std::string& name : AvailableConfigs()) configs += "\n  " + name;
  app.footer("CONFIG names in experiments/configs/ (docs/experiments.md):" + (configs.empty() ? std::string(" none found") : configs));
  Shard shard;
  const int exit_code = ParseCommandLine(app, argc, argv, "run_experiment", [&] {
    if (merge_dirs.empty() && config_arg.empty()) throw CLI::ValidationError("config", "a CONFIG or --merge DIR... is required");
    if (!merge_dirs.empty() && !config_arg.empty()) {
      throw CLI::ValidationError("--merge", "takes the config from the shard directories: give no CONFIG");
    }
    if (!merge_dirs.empty() && (!shard_text.empty() || trials > 0 || resume)) {
      throw CLI::ValidationError("--merge", "cannot be combined with --shard, --trials or --resume");
    }
    if (!shard_text.empty()) {
      try {
        shard = ParseShard(shard_text);
      } catch (const std::invalid_argument& e) {
        throw CLI::ValidationError(e.what());
      }
    }
  });
  if (exit_code >= 0) return exit_code;

  // An interrupted run leaves no temporary files; its finished jobs stay in the staging
  // directory for --resume.
  InstallTemporaryFileCleanup();
  DriverOptions options;
  options.resume = resume;
  options.command_line.assign(argv, argv + argc);
  options.run.threads = threads;
  options.run.shard = shard;
  ProgressBar bar(!quiet && StderrIsTerminal());
  if (bar.shown()) options.run.on_progress = [&bar](size_t done, size_t total) { bar.Update(done, total); };

  return RunProgram("run_experiment", [&] {
    std::string summary;
    if (!merge_dirs.empty()) {
      const std::string name = ReadExperimentConfig(JoinPath(merge_dirs[0], "config.resolved.json")).name;
      options.out_dir = out_dir.empty() ? DefaultOutputDir(name) : out_dir;
      const MergedRun merged = MergeAndWrite(merge_dirs, options);
      ReportExpectation(merged.config, merged.trials);
      summary = "merged " + std::to_string(merge_dirs.size()) + " directories, " + std::to_string(merged.trials.size()) + " trials";
    } else {
      options.config_file = FindConfigFile(config_arg);
      nlohmann::json document = ReadJsonFile(options.config_file);
      if (trials > 0) {
        if (!document.is_object()) throw ConfigError(options.config_file + ": top level: expected a JSON object");
        document["trials"] = trials;
      }
      const ExperimentConfig config = ExperimentConfigFromJson(document, options.config_file);
      if (out_dir.empty()) {
        out_dir = DefaultOutputDir(config.name);
        if (!shard.IsWhole()) {
          // Under raw/ (not committed); merge with --merge results/<name>/raw/shards/*.
          out_dir += "/raw/shards/" + std::to_string(shard.index) + "-of-" + std::to_string(shard.count);
        }
      }
      options.out_dir = out_dir;
      const ExperimentRun run = RunAndWrite(config, options);
      if (shard.IsWhole()) ReportExpectation(config, run.trials);
      summary = StringPrintf("%zu of %zu trials in %.1f s on %d threads", run.trials.size(), run.jobs_total,
                             run.wall_time_s, run.threads);
    }
    if (!no_plots && shard.IsWhole()) RunPlotScript(options.out_dir, quiet);
    if (!quiet) std::printf("run_experiment: %s: %s\n", options.out_dir.c_str(), summary.c_str());
    return 0;
  });
}
