#include "experiments/regression.h"

#include <cmath>

#include "common/table.h"

namespace slt {
namespace {

// Whether sweep point `point` has the values `at` asks for (empty: every point).
bool Selected(const ExperimentConfig& config, const nlohmann::json& at, const SweepPoint& point) {
  for (size_t a = 0; a < config.sweep.size(); ++a) {
    const auto it = at.find(config.sweep[a].parameter);
    if (it != at.end() && *it != point.values[a]) return false;
  }
  return true;
}

}  // namespace

std::string ReportNumber(double v) { return StringPrintf("%.4g", v); }

void Record(bool pass, const std::string& line, const std::string& failure, RegressionReport* report) {
  report->table += std::string(pass ? "  ok    " : "  FAIL  ") + line + "\n";
  if (!pass) report->failures.push_back(failure);
}

RegressionReport CheckExpectations(const ExperimentConfig& config, const std::vector<SummaryRow>& rows) {
  RegressionReport report;
  const std::vector<SweepPoint> points = ExpandSweep(config.sweep);
  // The row of method `id` at point p, or a failure.
  auto row_of = [&](const std::string& id, size_t p) -> const SummaryRow* {
    for (const SummaryRow& row : rows) {
      if (row.point == p && config.methods.at(row.method).Id() == id) return &row;
    }
    report.failures.push_back("'" + id + "' has no result at " + PointText(config, points[p]));
    return nullptr;
  };
  for (size_t p = 0; p < points.size(); ++p) {
    const std::string at = PointText(config, points[p]);
    for (const OrderingCheck& pair : config.expect_better) {
      if (!Selected(config, pair.at, points[p])) continue;
      const SummaryRow* better = row_of(pair.better, p);
      const SummaryRow* worse = row_of(pair.worse, p);
      for (size_t m = 0; better != nullptr && worse != nullptr && m < pair.metrics.size(); ++m) {
        const int metric = TrialMetricFromName(pair.metrics[m]);
        const double mine = better->metrics[metric].mean, theirs = worse->metrics[metric].mean;
        Record(std::isfinite(mine) && (!std::isfinite(theirs) || mine <= theirs),
               "'" + pair.better + "' " + pair.metrics[m] + " mean " + ReportNumber(mine) + " vs '" + pair.worse +
                   "' " + ReportNumber(theirs) + " at " + at,
               "the expected ordering is lost at " + at + ": '" + pair.worse + "' has a lower mean " + pair.metrics[m] +
                   " (" + ReportNumber(theirs) + ") than '" + pair.better + "' (" + ReportNumber(mine) + ")",
               &report);
      }
    }
    for (const BoundCheck& bound : config.expect_bounds) {
      const SummaryRow* row = Selected(config, bound.at, points[p]) ? row_of(bound.method, p) : nullptr;
      if (row == nullptr) continue;
      const double value = row->metrics[TrialMetricFromName(bound.metric)].mean *
                           (bound.percent_of_path ? 100.0 / row->metrics[kPathLengthM].mean : 1.0);
      const std::string what = "'" + bound.method + "' " + bound.metric + " mean" +
                               (bound.percent_of_path ? " as % of the path" : "");
      // The config check asks for at least one side.
      const std::string limit =
          bound.min && bound.max ? "in [" + ReportNumber(*bound.min) + ", " + ReportNumber(*bound.max) + "]"
          : bound.max            ? "<= " + ReportNumber(*bound.max)
                                 : ">= " + ReportNumber(*bound.min);
      Record(std::isfinite(value) && (!bound.max || value <= *bound.max) && (!bound.min || value >= *bound.min),
             what + " " + ReportNumber(value) + " " + limit + " at " + at,
             "the expected bound is lost at " + at + ": " + what + " = " + ReportNumber(value) + ", not " + limit,
             &report);
    }
  }
  if (!config.expect_better.empty()) report.table += "  ordering (mean rotation error):\n" + OrderingText(config, rows);
  return report;
}

}  // namespace slt
