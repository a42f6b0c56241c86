#include "experiments/regression.h"

#include <cmath>

#include "common/table.h"

namespace slt {
namespace {

std::string Num(double v) { return StringPrintf("%.4g", v); }

}  // namespace

RegressionReport CheckOrderings(const ExperimentConfig& config, const std::vector<SummaryRow>& rows) {
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
      bool selected = true;
      for (size_t a = 0; a < config.sweep.size(); ++a) {
        const auto it = pair.at.find(config.sweep[a].parameter);
        selected = selected && (it == pair.at.end() || *it == points[p].values[a]);
      }
      if (!selected) continue;
      const std::string at = PointText(config, points[p]);
      const SummaryRow* better = row_of(pair.better, p);
      const SummaryRow* worse = row_of(pair.worse, p);
      if (better == nullptr || worse == nullptr) {
        report.failures.push_back("'" + (better ? pair.worse : pair.better) + "' has no result at " + at);
        continue;
      }
      for (int metric : {kRotErrDeg, kTransErrM}) {
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
  if (!config.expect_better.empty()) report.table += "  ordering (mean rotation error):\n" + OrderingText(config, rows);
  return report;
}

}  // namespace slt
