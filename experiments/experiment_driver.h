// The whole run_experiment flow, as a library (the tests use it): run or merge, then write
// every output and draw the plots.
#pragma once

#include <string>
#include <vector>

#include "common/source_tree.h"
#include "experiments/experiment_config.h"
#include "experiments/experiment_output.h"
#include "experiments/experiment_runner.h"

namespace slt {

struct DriverOptions {
  std::string out_dir;
  RunOptions run;
  // Reuse the completed jobs of an earlier run of the same resolved config: the journal of an
  // interrupted run (StagingDir) or, when there is none, a finished run in out_dir.
  bool resume = false;
  std::string config_file;                // recorded in run.json
  std::vector<std::string> command_line;  // recorded in run.json
};

// Runs the experiment (or the shard), then writes raw/, config.resolved.json, and, for a whole
// run, the summaries; run.json last. Everything is written into StagingDir(out_dir)
// (common/file_io.h), which then replaces out_dir whole (its raw/shards/, other runs' shard
// outputs, is kept): an interrupted run never leaves new rows beside old summaries. While the
// jobs run the staging directory holds config.resolved.json and a journal of the finished jobs
// (raw/, rewritten every few seconds), which an interrupted run leaves for --resume. Does not plot.
ExperimentRun RunAndWrite(const ExperimentConfig& config, const DriverOptions& options);

// Combines shard directories (MergeShardOutputs) into options.out_dir: raw/, summaries,
// config.resolved.json, run.json (with every shard's run.json), written and swapped in as
// RunAndWrite's. Refuses an out_dir that is one of the shards or holds one outside raw/shards/
// (the swap would delete it). Returns the merged run.
MergedRun MergeAndWrite(const std::vector<std::string>& shard_dirs, const DriverOptions& options);

// The result directory of a config when --out is not given: <source tree>/results/<name> (or
// ./results/<name> when the source tree is gone).
inline std::string DefaultOutputDir(const std::string& name) { return SourceTreePath("results/" + name); }

// A config by path or by name in experiments/configs/ ("noise_sweep", "noise_sweep.json",
// "ci/noise_sweep_ci"), and the names there, sorted (common/source_tree.h).
inline std::string FindConfigFile(const std::string& name) {
  return FindNamedFile(name, "experiments/configs", ".json", "config");
}
inline std::vector<std::string> AvailableConfigs() { return FileNamesIn("experiments/configs", ".json"); }

// Runs scripts/plot_experiment.py DIR with RunPythonScript (common/source_tree.h). Throws
// std::runtime_error when the script fails.
void RunPlotScript(const std::string& dir, bool quiet = false);

}  // namespace slt
