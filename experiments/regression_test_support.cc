#include "experiments/regression_test_support.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "common/table.h"
#include "methods/pose_tracker.h"

namespace slt {
namespace {

constexpr double kRelative = 1.25;
constexpr double kRotFloorDeg = 0.02;
constexpr double kTransFloorM = 0.0005;

// The absolute floor of a metric of kReferenceMetrics: the rotations' in degrees, the others'
// (translations) in metres.
double ToleranceFloor(int metric) {
  return metric == kRotErrDeg || metric == kAteRotDeg ? kRotFloorDeg : kTransFloorM;
}

}  // namespace

RegressionReport CompareWithReference(const ExperimentConfig& config, const std::vector<SummaryRow>& rows,
                                      const CsvTable& reference, const nlohmann::json& reference_config) {
  RegressionReport report;
  const std::vector<SweepPoint> points = ExpandSweep(config.sweep);

  // The numbers only compare when the experiment is the same: a changed CI config needs a new
  // reference, not a tolerance failure.
  const nlohmann::json current = ExperimentConfigToJson(config);
  for (const char* key : {"trials", "seed", "simulation", "sweep", "metrics_frame"}) {
    if (!reference_config.contains(key) || reference_config[key] != current[key]) {
      report.failures.push_back(std::string("the config's '") + key + "' differs from the reference's (" +
                                (reference_config.contains(key) ? reference_config[key].dump() : "absent") + " there, " +
                                current[key].dump() + " here): regenerate the reference deliberately with "
                                "scripts/update_references.sh");
    }
  }
  if (!report.failures.empty()) return report;

  // Reference methods: id -> tracker name.
  std::map<std::string, std::string> reference_methods;
  if (reference_config.contains("methods") && reference_config["methods"].is_array()) {
    for (const nlohmann::json& m : reference_config["methods"]) {
      reference_methods[m.value("label", m.value("name", ""))] = m.value("name", "");
    }
  }
  const size_t method_column = reference.Column("method");
  for (const auto& row : reference.rows) {
    if (!reference_methods.count(row[method_column])) reference_methods[row[method_column]] = row[method_column];
  }
  const std::vector<std::string> registered = RegisteredTrackerNames();
  for (const auto& [id, name] : reference_methods) {
    if (std::find(registered.begin(), registered.end(), name) == registered.end()) {
      report.failures.push_back("reference method '" + id + "' (tracker '" + name +
                                "') is no longer registered: restore it, or regenerate the references "
                                "deliberately with scripts/update_references.sh");
    } else if (MethodIndex(config, id) < 0) {
      report.failures.push_back("reference method '" + id + "' was not run: the config no longer includes it "
                                "(regenerate the references with scripts/update_references.sh if intended)");
    }
  }

  // Reference rows by (method id, sweep point): the same sweep (checked above) has the same points.
  std::map<std::pair<std::string, std::string>, size_t> by_key;
  for (size_t r = 0; r < reference.rows.size(); ++r) {
    by_key[{reference.rows[r][method_column], reference.rows[r][reference.Column("point")]}] = r;
  }

  std::set<std::string> no_reference;
  for (const SummaryRow& row : rows) {
    const std::string& id = config.methods.at(row.method).Id();
    if (!reference_methods.count(id)) {
      no_reference.insert(id);
      continue;
    }
    const auto it = by_key.find({id, std::to_string(row.point)});
    const std::string at = "'" + id + "' at " + PointText(config, points.at(row.point));
    if (it == by_key.end()) {
      report.failures.push_back(at + ": no reference row (the sweep changed? regenerate with scripts/update_references.sh)");
      continue;
    }
    const std::vector<std::string>& ref = reference.rows[it->second];
    const double ref_finite = ParseDouble(ref[reference.Column("finite_trials")]);
    if (static_cast<double>(row.finite_trials) < ref_finite) {
      report.failures.push_back(at + ": " + std::to_string(row.finite_trials) + " trials with finite poses, reference " +
                                ReportNumber(ref_finite));
    }
    for (const std::string& name : config.reference_metrics) {
      const int metric = TrialMetricFromName(name);
      const double absolute_floor = ToleranceFloor(metric);
      const std::string column = name + "_mean";
      const double reference_value = ParseDouble(ref[reference.Column(column)]);
      const double current = row.metrics[metric].mean;
      const double limit = std::max(kRelative * reference_value, reference_value + absolute_floor);
      const std::string values = column + " = " + ReportNumber(current);
      Record(std::isfinite(current) && (!std::isfinite(reference_value) || current <= limit),
             at + "  " + values + "  (reference " + ReportNumber(reference_value) + ", limit " +
                 ReportNumber(limit) + ")",
             at + ": " + values + " exceeds the limit " + ReportNumber(limit) + " (reference " +
                 ReportNumber(reference_value) + "; limit = max(" + ReportNumber(kRelative) +
                 " x reference, reference + " + ReportNumber(absolute_floor) + "))",
             &report);
    }
  }
  for (const std::string& id : no_reference) {
    report.notes.push_back("'" + id + "': no reference (a method registered after the references were made); "
                           "not checked. Add it with scripts/update_references.sh");
  }
  return report;
}

}  // namespace slt
