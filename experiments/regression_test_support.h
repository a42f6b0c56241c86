// Test support of the CI regression check on accuracy curves (experiments_regression_test and
// its unit tests; no program calls it): a fresh summary against a committed reference
// (results/reference/<name>/, written by scripts/update_references.sh).
//
// Tolerance, per method present in both and per sweep point, for each metric of the config's
// reference_metrics (by default all of kReferenceMetrics: the mean rotation and the mean
// translation error at the metrics frame, and the error along the whole run, the mean ATE in
// rotation and translation and the mean largest translation error: a loop's final error can be
// small while its middle is far off, docs/long_sequences.md):
//     current <= max(kRelative * reference, reference + floor)
// with kRelative = 1.25 and floors 0.02 deg and 0.5 mm (so that a reference near zero does not
// fail on a change far below the noise). The number of trials with finite poses must not drop.
// A method registered later, absent from the reference, is reported as "no reference" and does
// not fail; a reference method that is no longer registered fails. A reference made with another
// experiment (trials, seed, simulation, sweep or metrics frame differ) fails: regenerate it.
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "common/csv.h"
#include "experiments/regression.h"

namespace slt {

// `reference_summary` is the reference's summary.csv, `reference_config` its
// config.resolved.json (the methods' tracker names are read from it).
RegressionReport CompareWithReference(const ExperimentConfig& config, const std::vector<SummaryRow>& rows,
                                      const CsvTable& reference_summary, const nlohmann::json& reference_config);

}  // namespace slt
