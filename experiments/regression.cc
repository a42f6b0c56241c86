#include "experiments/regression.h"

#include <cmath>

#include "common/table.h"

namespace slt {
namespace {

std::string Num(double v) { return StringPrintf("%.4g", v); }

// Whether sweep point `point` has the values `at` asks for (empty: every point).
bool Selected(const ExperimentConfig& config, const nlohmann::json& at, const SweepPoint& point) {
  for (size_t a = 0; a < config.sweep.size(); ++a) {
    const auto it = at.find(config.sweep[a].parameter);
    if (it != at.end() && *it != point.values[a]) return false;
  }
  return true;
}

}  // namespace

RegressionReport CheckExpectations(const ExperimentConfig& config, const std::vector<SummaryRow>& rows) {
  RegressionReport report;
  const std::vector<SweepPoint> points = ExpandSweep(config.sweep);
  auto row_of = [&](const std::string& id, size_t point) -> const SummaryRow* {
    for (const SummaryRow& row : rows) {
      if (row.point == point && config.methods.at(row.method).Id() == id) return &row;
    }
    return nullptr;
  };
  for (const OrderingCheck& pair : config.expect_better) {
    for (size_t p = 0; p < points.size(); ++p) {
      if (!Selected(config, pair.at, points[p])) continue;
      const std::string at = PointText(config, points[p]);
      const SummaryRow* better = row_of(pair.better, p);
      const SummaryRow* worse = row_of(pair.worse, p);
      if (better == nullptr || worse == nullptr) {
        report.failures.push_back("'" + (better ? pair.worse : pair.better) + "' has no result at " + at);
        continue;
      }
      for (const std::string& name : pair.metrics) {
        const int metric = TrialMetricFromName(name);
        const double mine = better->metrics[metric].mean, theirs = worse->metrics[metric].mean;
        const bool pass = std::isfinite(mine) && (!std::isfinite(theirs) || mine <= theirs);
        report.table += std::string(pass ? "  ok    " : "  FAIL  ") + "'" + pair.better + "' " + TrialMetricName(metric) +
                        " mean " + Num(mine) + " vs '" + pair.worse + "' " + Num(theirs) + " at " + at + "\n";
        if (!pass) {
          report.failures.push_back("the expected ordering is lost at " + at + ": '" + pair.worse + "' has a lower mean " +
                                    TrialMetricName(metric) + " (" + Num(theirs) + ") than '" + pair.better + "' (" +
                                    Num(mine) + ")");
        }
      }
    }
  }
  for (const BoundCheck& bound : config.expect_bounds) {
    const int metric = TrialMetricFromName(bound.metric);
    for (size_t p = 0; p < points.size(); ++p) {
      if (!Selected(config, bound.at, points[p])) continue;
      const std::string at = PointText(config, points[p]);
      const SummaryRow* row = row_of(bound.method, p);
      if (row == nullptr) {
        report.failures.push_back("'" + bound.method + "' has no result at " + at);
        continue;
      }
      double value = row->metrics[metric].mean;
      std::string what = bound.metric + " mean";
      if (bound.percent_of_path) {
        value *= 100.0 / row->metrics[kPathLengthM].mean;
        what += " as % of the path";
      }
      const bool pass = std::isfinite(value) && value >= bound.min && value <= bound.max;
      const std::string range = "[" + Num(bound.min) + ", " + (bound.max < 1e9 ? Num(bound.max) : "-") + "]";
      report.table += std::string(pass ? "  ok    " : "  FAIL  ") + "'" + bound.method + "' " + what + " " + Num(value) +
                      " in " + range + " at " + at + "\n";
      if (!pass) {
        report.failures.push_back("the expected bound is lost at " + at + ": '" + bound.method + "' " + what + " = " +
                                  Num(value) + ", outside " + range);
      }
    }
  }
  if (!config.expect_better.empty()) report.table += "  ordering (mean rotation error):\n" + OrderingText(config, rows);
  return report;
}

}  // namespace slt
