// The expected orderings and bounds of a config (expect_better, expect_bounds): checked by
// run_experiment (a note when one does not hold) and by the CI regression check (experiments/regression_test_support.h, which
// also compares with the committed references).
#pragma once

#include <string>
#include <vector>

#include "experiments/experiment_config.h"
#include "experiments/experiment_output.h"

namespace slt {

struct RegressionReport {
  std::vector<std::string> failures;  // empty = pass
  std::vector<std::string> notes;     // "no reference", methods not run, ...
  std::string table;                  // one line per compared value, for the log
  bool ok() const { return failures.empty(); }
};

// A number of the reports ("%.4g"), and one comparison: a line of report->table, and its
// failure when it does not hold.
std::string ReportNumber(double v);
void Record(bool pass, const std::string& line, const std::string& failure, RegressionReport* report);

// Every pair of config.expect_better at every sweep point it selects: `better` has the lower
// mean of each of the pair's metrics (by default the rotation and translation error at the
// metrics frame); every bound of config.expect_bounds at every point it selects holds (nothing
// to check when both are empty). The table lists each comparison and, with orderings, the full
// ordering at every point.
RegressionReport CheckExpectations(const ExperimentConfig& config, const std::vector<SummaryRow>& rows);

}  // namespace slt
