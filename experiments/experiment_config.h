// The experiment config: which simulated sequences, which trackers, how many trials, which
// sweep, which plots. docs/experiments.md lists every field.
//
// Every field has a default and is declared once, with its range and one-line doc, in the
// config's option schemas (experiment_config.cc, common/options.h): reading, checking and
// writing derive from them; the comments here say only what the schemas' docs do not.
// Errors are ConfigError "<file>: key '<dotted.key>': <reason>".
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "experiments/trial_result.h"
#include "frontend/image_sequence.h"
#include "simulator/simulation_config.h"

namespace slt {

// One swept parameter: a dotted key path into the simulation JSON and its values (JSON
// scalars: numbers, strings or booleans).
struct SweepAxis {
  std::string parameter;
  std::vector<nlohmann::json> values;
  std::string label;
};

// One tracker of the experiment. Its id in every output is its label (unique in a config).
struct MethodSpec {
  std::string name;
  std::string label;
  nlohmann::json options = nlohmann::json::object();  // passed to CreateTracker
  const std::string& Id() const { return label; }
};

// A value the paper reports, drawn on a sweep plot beside the reproduction (Figs. 4, 5).
struct ReportedValue {
  double x = std::nan("");  // required
  double rot_err_deg = -1.0;
  double trans_err_m = -1.0;
  bool upper_bound = true;
  std::string label = "paper";
};

// One PNG drawn by scripts/plot_experiment.py from the CSV outputs.
struct PlotSpec {
  std::string kind;
  std::string file;
  std::string title;
  std::string caption;
  std::string yscale = "linear";
  bool band = false;
  // Median solid, mean dotted for "both": one failed trial moves the mean, not the median.
  std::string statistic = "mean";
  // grid: "methods" = one panel per value of the second parameter, one line per method;
  // "sweep" = one panel per method, one line per value of the second parameter.
  std::string lines = "methods";
  int trial = 0;  // must be saved
  std::vector<ReportedValue> paper;
};

// An expected ordering: `better` has a lower mean than `worse` of each of `metrics` (by default
// the rotation and the translation error at the metrics frame), at every sweep point whose values
// match `at` (sweep parameter -> value; empty = every point). Checked by
// experiments_regression_test; a method not named in any pair (a new baseline) can rank anywhere.
struct OrderingCheck {
  std::string better;
  std::string worse;
  nlohmann::json at = nlohmann::json::object();
  std::vector<std::string> metrics = {"rot_err_deg", "trans_err_m"};
};

// An expected bound on one method's result, at every sweep point whose values match `at`:
//     min <= mean of `metric` over the trials with finite poses <= max,
// or, with percent_of_path, 100 * mean(metric) / mean(path_length_m) in [min, max] (the issue
// bounds of docs/long_sequences.md: ATE and maximum error as % of the path; the NEES inside the
// 95 % band of its chi-square distribution). Either side may be left out. Checked with the
// orderings (experiments/regression.h).
struct BoundCheck {
  std::string method;
  std::string metric;
  std::optional<double> max;  // none: no upper bound (null in JSON)
  bool percent_of_path = false;
  nlohmann::json at = nlohmann::json::object();
  std::optional<double> min;  // none: no lower bound
};

// A recorded stereo sequence (KITTI or EuRoC layout, frontend/image_sequence.h) run through the
// image front end instead of a simulation (docs/datasets.md).
struct DatasetSpec {
  std::string path;
  std::string label;
  DatasetLayout layout = DatasetLayout::kAuto;
  int first_frame = 0;
  int end_frame = -1;
  std::string ground_truth;
  // Tracker options of the platform that recorded it, per method name, merged over each
  // method's own options for the runs on this dataset (MethodOptionsOn): a tracker's motion
  // prior is a property of the platform, not of the tracker or the detector (a car at 10 Hz
  // moves ~1.2 m per frame, the paper's protocol ~1 cm; docs/datasets.md).
  nlohmann::json tracker_options = nlohmann::json::object();
};

// The metrics a CI config can compare with its reference (reference_metrics): the mean rotation
// and translation error at the metrics frame, the ATE in rotation and translation, the largest
// translation error.
inline constexpr std::array<TrialMetric, 5> kReferenceMetrics = {kRotErrDeg, kTransErrM, kAteRotDeg, kAteTransM,
                                                                 kMaxTransErrM};
// Their names (trial_result.h), in that order.
std::vector<std::string> ReferenceMetricNames();

struct ExperimentConfig {
  std::string name = "experiment";
  std::string title;
  int trials = 20;
  std::uint64_t seed = 1;
  // The base simulation JSON as given (SimulationConfigFromJson format, without "seed"). It is
  // kept as JSON, not resolved, because some simulation defaults depend on other fields
  // (scene.type) that a sweep may change.
  nlohmann::json simulation = nlohmann::json::object();
  std::vector<SweepAxis> sweep;
  std::vector<MethodSpec> methods;
  int metrics_frame = -1;  // -1 = the last frame of each sequence
  bool per_frame_curves = false;
  int save_trajectories = 0;
  std::vector<std::string> table_metrics = {"rot_err_deg", "trans_err_m", "time_us"};
  std::vector<PlotSpec> plots;
  std::vector<OrderingCheck> expect_better;
  std::vector<BoundCheck> expect_bounds;
  // The summary metrics experiments_regression_test compares with the committed reference
  // (experiments/regression_test_support.h): a subset of kReferenceMetrics, all by default.
  // A long run whose final and largest errors turn on the last bits of a library's arithmetic
  // (docs/experiments.md, "CI regression") is compared on its ATE only; its expect_bounds hold it
  // to the bounds on the rest.
  std::vector<std::string> reference_metrics = ReferenceMetricNames();
  // Recorded sequences instead of the simulation: then "simulation" and "sweep" must be absent,
  // trials is 1 (a recorded sequence has no random draws), and the sweep is one axis
  // "dataset" whose values are the datasets' labels, so that tables and plots group by dataset.
  std::vector<DatasetSpec> datasets;
  nlohmann::json frontend = nlohmann::json::object();
};

// Reads a config. `where` names the file in errors. "methods": "all" (or absent) expands to
// every registered tracker that is not plumbing_only, with default options, in registration
// order; "extra_methods" are appended.
ExperimentConfig ExperimentConfigFromJson(const nlohmann::json& j, const std::string& where);
ExperimentConfig ReadExperimentConfig(const std::string& path);
// Every field, defaults filled in, methods expanded (config.resolved.json): what
// ExperimentConfigFromJson reads back to the same config.
nlohmann::json ExperimentConfigToJson(const ExperimentConfig& config);
// ExperimentConfigToJson plus an output-only "resolved" section (ignored when read back):
// each method's description and resolved Options(), and the full simulation config of every
// sweep point. Creates each tracker once.
nlohmann::json ResolvedConfigJson(const ExperimentConfig& config);

// The options `method` runs with on `dataset`: its own, with the dataset's tracker_options for
// its tracker name merged over them (JSON merge patch, RFC 7396: the dataset's keys win).
nlohmann::json MethodOptionsOn(const MethodSpec& method, const DatasetSpec& dataset);

// A point of the sweep: one value per axis (empty for no sweep).
struct SweepPoint {
  std::vector<nlohmann::json> values;
};
// Every combination of the axes' values, the first axis outermost. One empty point for no
// sweep.
std::vector<SweepPoint> ExpandSweep(const std::vector<SweepAxis>& axes);

// The simulation config of a sweep point for trial `trial`: the base JSON with the point's
// values set, read by SimulationConfigFromJson, seed = TrialSeed(config.seed, trial). The seed
// does not depend on the point or the method: every sweep value and every method of trial k
// sees the same scene, motion and noise draws.
SimulationConfig TrialSimulation(const ExperimentConfig& config, const SweepPoint& point, int trial);

// "noise.endpoint_px = 1, outliers.rate = 0.1" ("(no sweep)" without a sweep).
std::string PointText(const ExperimentConfig& config, const SweepPoint& point);

// The index in config.methods of the method with this id; -1 when there is none.
int MethodIndex(const ExperimentConfig& config, const std::string& id);

// The frame at which errors are read for a sequence of `frames` frames.
int MetricsFrameFor(const ExperimentConfig& config, int frames);

// A value printed for CSV columns, file names and tables: numbers in the shortest form that
// reads back to the same double, strings as they are.
std::string FormatValue(const nlohmann::json& value);

}  // namespace slt
