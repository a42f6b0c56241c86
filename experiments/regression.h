// The CI regression check on accuracy curves: a fresh summary against a committed reference
// (results/reference/<name>/, written by scripts/update_references.sh).
//
// Tolerance, per method present in both and per sweep point, for the mean rotation and the mean
// translation error at the metrics frame:
//     current <= max(kRelative * reference, reference + floor)
// with kRelative = 1.25 and floors 0.02 deg and 0.5 mm (so that a reference near zero does not
// fail on a change far below the noise). The number of trials with finite poses must not drop.
// A method registered later, absent from the reference, is reported as "no reference" and does
// not fail; a reference method that is no longer registered fails. A reference made with another
// experiment (trials, seed, simulation, sweep or metrics frame differ) fails: regenerate it.
#pragma once

#include <string>
#include <vector>

#include "common/csv.h"
#include "experiments/experiment_config.h"
#include "experiments/experiment_output.h"

namespace slt {

struct RegressionReport {
  std::vector<std::string> failures;  // empty = pass
  std::vector<std::string> notes;     // "no reference", methods not run, ...
  std::string table;                  // one line per compared value, for the log
  bool ok() const { return failures.empty(); }
};

struct RegressionTolerance {
  double relative = 1.25;
  double rot_floor_deg = 0.02;
  double trans_floor_m = 0.0005;
};

// `reference_summary` is the reference's summary.csv, `reference_config` its
// config.resolved.json (the methods' tracker names are read from it).
RegressionReport CompareWithReference(const ExperimentConfig& config, const std::vector<SummaryRow>& rows,
                                      const CsvTable& reference_summary, const nlohmann::json& reference_config,
                                      const RegressionTolerance& tolerance = {});

// Every pair of config.expect_better at every sweep point it selects: `better` has the lower
// mean rotation and translation error at the metrics frame (nothing to check when empty). The
// table also lists the full ordering at every point.
RegressionReport CheckOrderings(const ExperimentConfig& config, const std::vector<SummaryRow>& rows);

}  // namespace slt
