// experiments_regression_test: reruns every fast config of experiments/configs/ci/ and fails
// when a method's mean error grows beyond the tolerance over the committed reference in
// results/reference/<name>/ (experiments/regression_test_support.h states the tolerance), or when the
// config's expected best method (the paper's ordering) loses its place.
//
// The fresh outputs are written to <build>/experiments/regression/<name>/ for inspection.
// Updating the references is deliberate: scripts/update_references.sh.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iostream>

#include "common/json_reader.h"
#include "common/csv.h"
#include "experiments/experiment_driver.h"
#include "experiments/regression_test_support.h"

namespace slt {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> CiConfigs() {
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(fs::path(SLT_SOURCE_DIR) / "experiments/configs/ci")) {
    if (entry.path().extension() == ".json") files.push_back(entry.path().stem().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

class ExperimentsRegression : public ::testing::TestWithParam<std::string> {};

TEST_P(ExperimentsRegression, WithinToleranceOfTheReference) {
  const std::string config_path = (fs::path(SLT_SOURCE_DIR) / "experiments/configs/ci" / (GetParam() + ".json")).string();
  const ExperimentConfig config = ReadExperimentConfig(config_path);
  // results/reference/<file name>: what scripts/update_references.sh writes.
  const fs::path reference_dir = fs::path(SLT_SOURCE_DIR) / "results/reference" / GetParam();

  DriverOptions options;
  options.out_dir = (fs::path(SLT_REGRESSION_OUT_DIR) / config.name).string();
  options.config_file = config_path;
  const ExperimentRun run = RunAndWrite(config, options);
  const std::vector<SummaryRow> rows = SummarizeTrials(config, run.trials);
  std::cout << config.name << ": " << run.trials.size() << " trials in " << run.wall_time_s << " s on " << run.threads
            << " threads; outputs in " << options.out_dir << "\n";

  const RegressionReport ordering = CheckExpectations(config, rows);
  std::cout << ordering.table;
  for (const std::string& f : ordering.failures) ADD_FAILURE() << config.name << ": " << f;

  if (!fs::exists(reference_dir / "summary.csv") || !fs::exists(reference_dir / "config.resolved.json")) {
    FAIL() << config.name << ": no reference in " << reference_dir.string()
           << " (make it deliberately with scripts/update_references.sh)";
  }
  const RegressionReport report = CompareWithReference(config, rows, ReadCsvFile((reference_dir / "summary.csv").string()),
                                                       ReadJsonFile((reference_dir / "config.resolved.json").string()));
  std::cout << report.table;
  for (const std::string& n : report.notes) std::cout << "  note: " << n << "\n";
  for (const std::string& f : report.failures) ADD_FAILURE() << config.name << ": " << f;
}

INSTANTIATE_TEST_SUITE_P(Ci, ExperimentsRegression, ::testing::ValuesIn(CiConfigs()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace slt
