#include "experiments/experiment_config.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/csv.h"
#include "common/json_reader.h"
#include "common/options.h"
#include "common/random.h"
#include "experiments/trial_result.h"
#include "frontend/frontend_options.h"
#include "frontend/image_sequence.h"
#include "methods/pose_tracker.h"

namespace slt {
namespace {

bool IsScalar(const nlohmann::json& v) { return v.is_number() || v.is_string() || v.is_boolean(); }

// An error of a part read on its own (tracker options, a simulation), moved under `key` of this
// file: "<where>: key '<key>.<its key>': ..." (with `suffix` appended).
[[noreturn]] void RethrowUnder(const ConfigError& e, const std::string& where, const std::string& key,
                               const std::string& suffix = "") {
  const std::string message = e.what();
  const std::string prefix = where + ": key '";
  if (message.compare(0, prefix.size(), prefix) == 0) {
    throw ConfigError(prefix + key + "." + message.substr(prefix.size()) + suffix);
  }
  throw ConfigError(prefix + key + "': " + message + suffix);
}

const OptionSchema<MethodSpec>& MethodSchema() {
  using M = MethodSpec;
  static const OptionSchema<M> schema = OptionSchema<M>()
                                            .Field("name", &M::name, {}, "registered tracker name")
                                            .Field("label", &M::label, {}, "its id in every output (default: the name)")
                                            .Field("options", &M::options, "tracker options (track --list-options)");
  return schema;
}

// A tracker name, or {"name", "label", "options"}.
MethodSpec ReadMethod(const nlohmann::json& j, const std::string& where, const std::string& key) {
  MethodSpec method;
  if (j.is_string()) {
    method.name = j.get<std::string>();
  } else if (j.is_object()) {
    JsonReader reader(j, where, key);
    MethodSchema().ReadFields(reader, &method);
    reader.RejectUnknownKeys();
    if (method.name.empty()) reader.Fail("name", "missing: the registered tracker name");
  } else {
    ThrowOptionError(where, "", key, std::string("expected a tracker name or {\"name\": ..}, got ") + j.type_name());
  }
  if (method.label.empty()) method.label = method.name;
  // An unknown tracker or invalid options fail here, naming the key, rather than in the middle
  // of a run.
  try {
    CreateTracker(method.name, method.options, where);
  } catch (const std::invalid_argument& e) {
    ThrowOptionError(where, "", key, e.what());
  } catch (const ConfigError& e) {
    RethrowUnder(e, where, j.is_object() ? key + ".options" : key);
  }
  return method;
}

// Appends the methods of `key`: an array, or (allow_all) "all" or absent for every registered
// tracker that is not plumbing_only, with default options.
void ReadMethodList(JsonReader& reader, const std::string& key, bool allow_all, std::vector<MethodSpec>* methods) {
  const nlohmann::json* v = reader.Find(key);
  if (allow_all && (v == nullptr || (v->is_string() && v->get<std::string>() == "all"))) {
    for (const std::string& name : RegisteredTrackerNames(false)) methods->push_back({name, name});
    return;
  }
  if (v == nullptr) return;
  if (!v->is_array()) reader.Fail(key, std::string(allow_all ? "expected \"all\" or " : "expected ") + "an array of methods");
  for (size_t i = 0; i < v->size(); ++i) methods->push_back(ReadMethod((*v)[i], reader.where(), IndexedKey(reader.KeyPath(key), i)));
}

const OptionSchema<SweepAxis>& AxisSchema() {
  using A = SweepAxis;
  static const OptionSchema<A> schema =
      OptionSchema<A>()
          .Field("parameter", &A::parameter, {}, "a dotted key of the simulation config")
          .Custom(
              "values",
              [](JsonReader& r, A* a) {
                const nlohmann::json* values = r.Find("values");
                if (values == nullptr) return;  // Check: required
                if (!values->is_array() || values->empty()) r.Fail("values", "expected a non-empty array");
                for (size_t i = 0; i < values->size(); ++i) {
                  if (!IsScalar((*values)[i])) r.Fail(IndexedKey("values", i), "expected a number, string or boolean");
                }
                a->values = values->get<std::vector<nlohmann::json>>();
                const size_t repeat = FirstRepeat(a->values, [](const nlohmann::json& v) { return v; });
                if (repeat < a->values.size()) {
                  r.Fail(IndexedKey("values", repeat), "duplicate value " + a->values[repeat].dump());
                }
              },
              [](const A& a) { return nlohmann::json(a.values); }, "array of numbers, strings or booleans",
              "the values, in the order of the tables and plots")
          .Field("label", &A::label, {}, "axis label for plots and tables (default: the parameter)")
          .OnRead([](A* a) {
            if (a->label.empty()) a->label = a->parameter;
          })
          .Check("parameter", [](const A& a) { return a.parameter.empty() ? "missing: a dotted key of the simulation config" : ""; })
          .Check("parameter", [](const A& a) {
            return a.parameter == "seed" ? "'seed' cannot be swept (trials set it; use the top-level 'seed' or 'trials')" : "";
          })
          .Check("values", [](const A& a) { return a.values.empty() ? "expected a non-empty array" : ""; });
  return schema;
}

const OptionSchema<ReportedValue>& ReportedValueSchema() {
  using R = ReportedValue;
  static const OptionSchema<R> schema =
      OptionSchema<R>()
          .Field("x", &R::x, AnyNumber(), "the value of the swept parameter (any number on a \"methods\" plot)")
          .Field("rot_err_deg", &R::rot_err_deg, AnyNumber(), "reported rotation error, degrees (< 0: not reported)")
          .Field("trans_err_m", &R::trans_err_m, AnyNumber(), "reported translation error, metres (< 0: not reported)")
          .Field("upper_bound", &R::upper_bound, "the paper says \"less than\" this value")
          .Field("label", &R::label, {}, "legend text")
          .Check("x", [](const R& v) {
            return std::isnan(v.x) ? "required: the value of the swept parameter (any number on a \"methods\" plot)" : "";
          })
          .Check("rot_err_deg", [](const R& v) {
            return v.rot_err_deg < 0.0 && v.trans_err_m < 0.0 ? "give rot_err_deg, trans_err_m or both (>= 0)" : "";
          });
  return schema;
}

const OptionSchema<PlotSpec>& PlotSchema() {
  using P = PlotSpec;
  static const OptionSchema<P> schema =
      OptionSchema<P>()
          .Field("kind", &P::kind, {"sweep", "grid", "curves", "trajectory", "methods"}, "what is drawn")
          .Field("file", &P::file, {}, "PNG file name in the output directory")
          .Field("title", &P::title, {}, "figure title (default: the experiment's)")
          .Field("caption", &P::caption, {}, "a line of text under the figure (optional)")
          .Field("yscale", &P::yscale, {"linear", "log"}, "error axis")
          .Field("band", &P::band, "shade the 95 % interval over trials")
          .Field("statistic", &P::statistic, {"mean", "median", "both"},
                 "sweep, grid, curves: the statistic over trials drawn as lines (both: median solid, mean dotted)")
          .Field("lines", &P::lines, {"methods", "sweep"}, "grid: one line per method or per second value")
          .Field("trial", &P::trial, AtLeast(0), "trajectory: the trial drawn")
          .Array("paper", &P::paper, ReportedValueSchema(),
                 "sweep: the paper's values drawn as black triangles; methods: as dashed lines")
          .Check("file", [](const P& p) {
            return p.file.size() < 5 || p.file.substr(p.file.size() - 4) != ".png" || p.file.find('/') != std::string::npos
                       ? "expected a file name ending in .png (no directory)"
                       : "";
          });
  return schema;
}

// " name name ...": the names of `metrics`, for error messages.
template <typename Metrics>
std::string KnownMetrics(const Metrics& metrics) {
  std::string known;
  for (const int m : metrics) known += std::string(" ") + TrialMetricName(m);
  return known;
}

// "" for a trial metric's name, else "unknown metric '<name>' (known: ...)".
std::string MetricNameError(const std::string& metric) {
  if (TrialMetricFromName(metric) >= 0) return "";
  std::array<int, kNumTrialMetrics> all;
  for (int m = 0; m < kNumTrialMetrics; ++m) all[m] = m;
  return "unknown metric '" + metric + "' (known:" + KnownMetrics(all) + ")";
}

// Trial metric names at `key` ("time_us": time_mean_us); an unknown one fails with the list.
void ReadMetricNames(JsonReader& r, const std::string& key, std::vector<std::string>* names) {
  r.Get(key, names);
  for (size_t i = 0; i < names->size(); ++i) {
    if ((*names)[i] == "time_us") (*names)[i] = TrialMetricName(kTimeMeanUs);
    const std::string error = MetricNameError((*names)[i]);
    if (!error.empty()) r.Fail(IndexedKey(key, i), error);
  }
}

constexpr const char* kAtDoc = "the sweep points checked: {\"<swept parameter>\": value} (empty: every point)";

const OptionSchema<OrderingCheck>& OrderingSchema() {
  using O = OrderingCheck;
  static const OptionSchema<O> schema =
      OptionSchema<O>()
          .Field("better", &O::better, {}, "id of the method with the lower errors")
          .Field("worse", &O::worse, {}, "id of the method with the higher errors")
          .Field("at", &O::at, kAtDoc)
          .Custom(
              "metrics", [](JsonReader& r, O* o) { ReadMetricNames(r, "metrics", &o->metrics); },
              [](const O& o) { return nlohmann::json(o.metrics); }, "metric names",
              "trial metrics compared (means over the trials)",
              [](const O& o) { return o.metrics.empty() ? "at least one metric" : ""; });
  return schema;
}

const OptionSchema<BoundCheck>& BoundSchema() {
  using B = BoundCheck;
  static const OptionSchema<B> schema =
      OptionSchema<B>()
          .Field("method", &B::method, {}, "id of the method bounded")
          .Field("metric", &B::metric, {}, "a trial metric (summary.csv's columns without _mean)")
          .Field("max", &B::max, AnyNumber(), "highest mean allowed")
          .Field("min", &B::min, AnyNumber(), "lowest mean allowed")
          .Field("percent_of_path", &B::percent_of_path, "bound 100 mean(metric) / mean(path_length_m) instead")
          .Field("at", &B::at, kAtDoc)
          .Check("metric", [](const B& b) { return MetricNameError(b.metric); })
          .Check("max", [](const B& b) {
            return !b.max && !b.min ? "give max, min or both" : b.min && b.max && *b.min > *b.max ? "below min" : "";
          });
  return schema;
}

const OptionSchema<DatasetSpec>& DatasetSchema() {
  using D = DatasetSpec;
  static const OptionSchema<D> schema =
      OptionSchema<D>()
          .Field("path", &D::path, {}, "the sequence folder, relative to the working directory")
          .Field("label", &D::label, {}, "its id in every output (default: the folder's name)")
          .Field("layout", &D::layout, DatasetLayoutNames(), "the folder's layout (euroc = asl)")
          .Field("first_frame", &D::first_frame, AtLeast(0), "first stereo pair run")
          .Field("end_frame", &D::end_frame, AnyNumber(), "stereo pairs [first_frame, end_frame); -1 = to the end")
          .Field("ground_truth", &D::ground_truth, {}, "overrides the dataset's own ground truth file (\"\" = its own)")
          .Field("tracker_options", &D::tracker_options,
                 "per tracker name: options merged over the method's own on this dataset (its platform's motion)")
          .OnRead([](D* d) {
            const std::filesystem::path path = std::filesystem::path(d->path).lexically_normal();
            if (d->label.empty()) d->label = path.filename().string();
            if (d->label.empty()) d->label = path.parent_path().filename().string();
          })
          .Check("path", [](const D& d) { return d.path.empty() ? "missing: the sequence folder" : ""; })
          .Check("end_frame", [](const D& d) {
            return d.end_frame != -1 && d.end_frame <= d.first_frame ? "must be > first_frame, or -1 (to the end)" : "";
          })
          .Check("tracker_options", [](const D& d) {
            for (const auto& [name, options] : d.tracker_options.items()) {
              try {
                FindTracker(name);
              } catch (const std::invalid_argument& e) {
                return std::string(e.what());
              }
              if (!options.is_object()) return "'" + name + "': expected an object of tracker options";
            }
            return std::string();
          });
  return schema;
}

// Every field of a config but the cross-field checks (ExperimentConfigFromJson).
const OptionSchema<ExperimentConfig>& ExperimentSchema() {
  using C = ExperimentConfig;
  static const OptionSchema<C> schema =
      OptionSchema<C>()
          .Field("name", &C::name, {}, "output directory name: results/<name>")
          .Field("title", &C::title, {}, "title of the tables and plots (default: the name)")
          .Field("trials", &C::trials, AtLeast(1), "trials per method and sweep point")
          .Field("seed", &C::seed, AnyNumber(), "trial k simulates with seed TrialSeed(seed, k)")
          .Field("simulation", &C::simulation, "the base simulation (docs/simulation.md), without \"seed\"")
          .Array("datasets", &C::datasets, DatasetSchema(), "recorded sequences instead of the simulation")
          .Field("frontend", &C::frontend, "front-end options for \"datasets\" (docs/frontend.md)")
          .Array("sweep", &C::sweep, AxisSchema(), "0, 1 or 2 swept parameters (2: every combination)")
          .Custom(
              "methods", [](JsonReader& r, C* c) { ReadMethodList(r, "methods", true, &c->methods); },
              [](const C& c) {
                nlohmann::json methods = nlohmann::json::array();
                for (const MethodSpec& m : c.methods) methods.push_back(MethodSchema().ToJson(m));
                return methods;
              },
              "\"all\" or array", "trackers: names or {name, label, options}; \"all\": every registered one")
          .Custom(
              "extra_methods", [](JsonReader& r, C* c) { ReadMethodList(r, "extra_methods", false, &c->methods); },
              nullptr, "array", "appended to \"methods\" (read only)")
          .Custom(
              "metrics_frame",
              [](JsonReader& r, C* c) {
                const nlohmann::json* mf = r.Find("metrics_frame");
                if (mf == nullptr || (mf->is_string() && mf->get<std::string>() == "last")) return;
                if (!mf->is_number_integer() || mf->get<long long>() < 0 || mf->get<long long>() >= (1LL << 30)) {
                  r.Fail("metrics_frame", "expected a frame index >= 0 or \"last\"");
                }
                c->metrics_frame = mf->get<int>();
              },
              [](const C& c) { return c.metrics_frame < 0 ? nlohmann::json("last") : nlohmann::json(c.metrics_frame); },
              "\"last\" or >= 0", "frame at which the accumulated error is read")
          .Field("per_frame_curves", &C::per_frame_curves, "write per-frame error curves (Fig. 6)")
          .Field("save_trajectories", &C::save_trajectories, AtLeast(0), "trials 0 .. n-1 write TUM trajectories")
          .Custom(
              "table_metrics", [](JsonReader& r, C* c) { ReadMetricNames(r, "table_metrics", &c->table_metrics); },
              [](const C& c) { return nlohmann::json(c.table_metrics); }, "metric names", "summary table columns")
          .Array("plots", &C::plots, PlotSchema(), "PNGs drawn (default: follow the sweep and the flags)")
          .Array("expect_better", &C::expect_better, OrderingSchema(), "expected orderings, as pairs")
          .Array("expect_bounds", &C::expect_bounds, BoundSchema(), "expected bounds on a method's mean metrics")
          .Custom(
              "reference_metrics",
              [](JsonReader& r, C* c) { ReadMetricNames(r, "reference_metrics", &c->reference_metrics); },
              [](const C& c) { return nlohmann::json(c.reference_metrics); }, "metric names",
              "the metrics experiments_regression_test compares with the committed reference",
              [](const C& c) -> std::string {
                if (c.reference_metrics.empty()) return "at least one metric";
                for (const std::string& m : c.reference_metrics) {
                  if (std::find(kReferenceMetrics.begin(), kReferenceMetrics.end(), TrialMetricFromName(m)) ==
                      kReferenceMetrics.end()) {
                    return "'" + m + "' is not compared with references (known:" + KnownMetrics(kReferenceMetrics) + ")";
                  }
                }
                return "";
              })
          .Check("name",
                 [](const C& c) {
                   return c.name.empty() || c.name.find_first_of("/\\ ") != std::string::npos || c.name[0] == '.'
                              ? "expected a non-empty name without '/', '\\' or spaces (it names the output directory)"
                              : "";
                 })
          .Check("sweep", [](const C& c) { return c.sweep.size() > 2 ? "at most 2 swept parameters" : ""; })
          .Check("sweep[1].parameter",
                 [](const C& c) {
                   return c.sweep.size() == 2 && c.sweep[0].parameter == c.sweep[1].parameter ? "the same parameter as sweep[0]"
                                                                                              : "";
                 })
          .Check("methods", [](const C& c) {
            const size_t repeat = FirstRepeat(c.methods, [](const MethodSpec& m) { return m.label; });
            if (repeat < c.methods.size()) {
              return "two methods have the id '" + c.methods[repeat].label + "' (give the second a distinct \"label\")";
            }
            return c.methods.empty() ? std::string("no method to run") : std::string();
          });
  return schema;
}

std::vector<PlotSpec> DefaultPlots(const ExperimentConfig& c) {
  std::vector<PlotSpec> plots;
  const auto add = [&](const char* kind, const std::string& file) {
    plots.emplace_back();
    plots.back().kind = kind;
    plots.back().file = c.name + file;
  };
  if (c.sweep.size() == 1 && c.datasets.empty()) add("sweep", ".png");  // datasets: categories, no sweep curve
  if (c.sweep.size() == 2) add("grid", ".png");
  if (c.per_frame_curves) add("curves", "_curves.png");
  if (c.save_trajectories > 0) add("trajectory", "_trajectory.png");
  return plots;
}

void CheckPlot(const ExperimentConfig& c, const PlotSpec& plot, const std::string& where, const std::string& key) {
  auto fail = [&](const std::string& reason) { ThrowOptionError(where, key, "kind", reason); };
  if (plot.kind == "sweep" && c.sweep.size() != 1) fail("\"sweep\" plots need exactly one swept parameter");
  if (plot.kind == "grid" && c.sweep.size() != 2) fail("\"grid\" plots need two swept parameters");
  if (plot.kind == "curves" && !c.per_frame_curves) fail("\"curves\" plots need \"per_frame_curves\": true");
  if (!plot.paper.empty() && plot.kind != "sweep" && plot.kind != "methods") {
    ThrowOptionError(where, key, "paper", "the paper's values are drawn on \"sweep\" and \"methods\" plots only");
  }
  if (plot.kind == "trajectory" && plot.trial >= c.save_trajectories) {
    ThrowOptionError(where, key, "trial", "trial " + std::to_string(plot.trial) +
                                              " is not saved (\"save_trajectories\" is " +
                                              std::to_string(c.save_trajectories) + ")");
  }
}

// An ordering's or a bound's methods (field -> id) are methods of the config, and its `at`
// selects values of swept parameters.
void CheckExpectation(const ExperimentConfig& c, const std::vector<std::pair<const char*, std::string>>& methods,
                      const nlohmann::json& at, const std::string& where, const std::string& key) {
  for (const auto& [field, id] : methods) {
    if (MethodIndex(c, id) < 0) ThrowOptionError(where, key, field, "'" + id + "' is not the id of a method of this config");
  }
  for (const auto& [parameter, value] : at.items()) {
    bool found = false;
    for (const SweepAxis& a : c.sweep) {
      found = found || (a.parameter == parameter && std::find(a.values.begin(), a.values.end(), value) != a.values.end());
    }
    if (!found) ThrowOptionError(where, key, "at", parameter + " = " + value.dump() + " is not a value of a swept parameter");
  }
}

// The simulation of a sweep point: the base JSON with the point's values set, read and checked. Errors read "<where>: key 'simulation.<key>': <reason>", with
// " (at sweep point <point>)" appended for a point with values.
SimulationConfig PointSimulation(const ExperimentConfig& c, const SweepPoint& point, const std::string& where) {
  nlohmann::json sim = c.simulation;
  for (size_t a = 0; a < point.values.size(); ++a) {
    try {
      SetDottedKey(&sim, c.sweep[a].parameter, point.values[a]);
    } catch (const std::invalid_argument& e) {
      ThrowOptionError(where, IndexedKey("sweep", a), "parameter", e.what());
    }
  }
  try {
    SimulationConfig config = SimulationConfigFromJson(sim, where);
    config.Check(where);
    return config;
  } catch (const ConfigError& e) {
    RethrowUnder(e, where, "simulation", point.values.empty() ? "" : " (at sweep point " + PointText(c, point) + ")");
  }
}

// The checks of a run on recorded sequences; their labels become the one sweep axis "dataset".
void UseDatasetsAsSweep(JsonReader& reader, ExperimentConfig* c) {
  if (c->datasets.empty()) reader.Fail("datasets", "expected a non-empty array of {\"path\", ...}");
  const size_t repeat = FirstRepeat(c->datasets, [](const DatasetSpec& d) { return d.label; });
  if (repeat < c->datasets.size()) {
    ThrowOptionError(reader.where(), IndexedKey("datasets", repeat), "label", "'" + c->datasets[repeat].label + "' used twice");
  }
  if (reader.Has("simulation")) reader.Fail("simulation", "not with \"datasets\" (a run is on recorded or on simulated data)");
  if (c->trials != 1) reader.Fail("trials", "must be 1 with \"datasets\" (a recorded sequence has no random draws)");
  SweepAxis axis;
  axis.parameter = axis.label = "dataset";
  for (const DatasetSpec& d : c->datasets) axis.values.push_back(d.label);
  // config.json writes this axis (for the plots); reading it back, it must be just that.
  const auto as_json = [](const SweepAxis& a) { return AxisSchema().ToJson(a); };
  if (reader.Has("sweep") && (c->sweep.size() != 1 || as_json(c->sweep[0]) != as_json(axis))) {
    reader.Fail("sweep", "not with \"datasets\" (the datasets are the sweep)");
  }
  c->sweep = {axis};
}

}  // namespace

std::vector<std::string> ReferenceMetricNames() {
  std::vector<std::string> names;
  for (const TrialMetric m : kReferenceMetrics) names.emplace_back(TrialMetricName(m));
  return names;
}

ExperimentConfig ExperimentConfigFromJson(const nlohmann::json& j, const std::string& where) {
  JsonReader reader(j, where);
  ExperimentConfig c;
  ExperimentSchema().ReadFields(reader, &c);
  reader.Find("resolved");  // output only (ResolvedConfigJson): ignored on input
  reader.RejectUnknownKeys();
  ExperimentSchema().Validate(c, where, "");
  if (c.title.empty()) c.title = c.name;
  c.save_trajectories = std::min(c.save_trajectories, c.trials);
  if (reader.Has("datasets")) UseDatasetsAsSweep(reader, &c);
  try {
    FrontEndOptionsFromJson(c.frontend, where);
  } catch (const ConfigError& e) {
    RethrowUnder(e, where, "frontend");  // "<where>: key 'frontend.x': reason"
  }
  if (c.simulation.contains("seed")) {
    ThrowOptionError(where, "simulation", "seed", "set by the experiment (trial k uses TrialSeed(seed, k)); use the top-level 'seed'");
  }

  if (!reader.Has("plots")) c.plots = DefaultPlots(c);
  for (size_t i = 0; i < c.plots.size(); ++i) {
    CheckPlot(c, c.plots[i], where, IndexedKey("plots", i));
    if (c.plots[i].title.empty()) c.plots[i].title = c.title;
  }
  const size_t repeat = FirstRepeat(c.plots, [](const PlotSpec& p) { return p.file; });
  if (repeat < c.plots.size()) ThrowOptionError(where, IndexedKey("plots", repeat), "file", "used twice");
  for (size_t i = 0; i < c.expect_better.size(); ++i) {
    const OrderingCheck& o = c.expect_better[i];
    CheckExpectation(c, {{"better", o.better}, {"worse", o.worse}}, o.at, where, IndexedKey("expect_better", i));
  }
  for (size_t i = 0; i < c.expect_bounds.size(); ++i) {
    const BoundCheck& b = c.expect_bounds[i];
    CheckExpectation(c, {{"method", b.method}}, b.at, where, IndexedKey("expect_bounds", i));
  }

  if (!c.datasets.empty()) {
    // Frame counts are known when the datasets are opened; errors are read at the last frame.
    if (c.metrics_frame != -1) reader.Fail("metrics_frame", "must be \"last\" with \"datasets\"");
    // Each method's options on each dataset must make a tracker, as its own do (ReadMethod).
    for (size_t i = 0; i < c.datasets.size(); ++i) {
      for (const MethodSpec& m : c.methods) {
        if (!c.datasets[i].tracker_options.contains(m.name)) continue;
        try {
          CreateTracker(m.name, MethodOptionsOn(m, c.datasets[i]), where);
        } catch (const ConfigError& e) {
          RethrowUnder(e, where, IndexedKey("datasets", i) + ".tracker_options." + m.name);
        }
      }
    }
    return c;
  }
  // Every sweep point must give a valid simulation (the base alone is never run), and the metrics
  // frame must exist in it.
  for (const SweepPoint& point : ExpandSweep(c.sweep)) {
    const SimulationConfig config = PointSimulation(c, point, where);
    if (c.metrics_frame >= config.frames) {
      reader.Fail("metrics_frame", "frame " + std::to_string(c.metrics_frame) + " does not exist in a sequence of " +
                                       std::to_string(config.frames) + " frames (frames count from 0)");
    }
  }
  return c;
}

nlohmann::json MethodOptionsOn(const MethodSpec& method, const DatasetSpec& dataset) {
  nlohmann::json options = method.options;
  if (dataset.tracker_options.contains(method.name)) options.merge_patch(dataset.tracker_options.at(method.name));
  return options;
}

ExperimentConfig ReadExperimentConfig(const std::string& path) {
  return ExperimentConfigFromJson(ReadJsonFile(path), path);
}

nlohmann::json ExperimentConfigToJson(const ExperimentConfig& c) {
  nlohmann::json j = ExperimentSchema().ToJson(c);
  // A run is on simulated or on recorded data: the other's keys are left out.
  if (c.datasets.empty()) {
    j.erase("datasets");
    j.erase("frontend");
  } else {
    j.erase("simulation");
  }
  return j;
}

nlohmann::json ResolvedConfigJson(const ExperimentConfig& c) {
  nlohmann::json j = ExperimentConfigToJson(c);
  nlohmann::json resolved;
  resolved["note"] = "output only: ignored when this file is read back as a config";
  resolved["methods"] = nlohmann::json::array();
  for (const MethodSpec& m : c.methods) {
    const TrackerInfo& info = FindTracker(m.name);
    resolved["methods"].push_back({{"id", m.Id()},
                                   {"name", m.name},
                                   {"description", info.description},
                                   {"minimum_lines", info.minimum_lines},
                                   {"options", CreateTracker(m.name, m.options, "methods")->Options()}});
  }
  resolved["points"] = nlohmann::json::array();
  const std::vector<SweepPoint> points = ExpandSweep(c.sweep);
  for (size_t p = 0; p < points.size(); ++p) {
    nlohmann::json values = nlohmann::json::object();
    for (size_t a = 0; a < c.sweep.size(); ++a) values[c.sweep[a].parameter] = points[p].values[a];
    if (!c.datasets.empty()) {
      resolved["points"].push_back({{"point", p}, {"values", values}, {"dataset", DatasetSchema().ToJson(c.datasets[p])}});
      continue;
    }
    nlohmann::json sim = SimulationConfigToJson(TrialSimulation(c, points[p], 0));
    sim["seed"] = "TrialSeed(seed, trial)";
    resolved["points"].push_back({{"point", p}, {"values", values}, {"simulation", sim}});
  }
  j["resolved"] = resolved;
  return j;
}

std::vector<SweepPoint> ExpandSweep(const std::vector<SweepAxis>& axes) {
  std::vector<SweepPoint> points(1);
  for (const SweepAxis& axis : axes) {
    std::vector<SweepPoint> next;
    for (const SweepPoint& p : points) {
      for (const nlohmann::json& v : axis.values) {
        next.push_back(p);
        next.back().values.push_back(v);
      }
    }
    points.swap(next);
  }
  return points;
}

SimulationConfig TrialSimulation(const ExperimentConfig& config, const SweepPoint& point, int trial) {
  SimulationConfig s = PointSimulation(config, point, config.name);
  s.seed = TrialSeed(config.seed, static_cast<std::uint64_t>(trial));
  return s;
}

std::string PointText(const ExperimentConfig& config, const SweepPoint& point) {
  if (config.sweep.empty()) return "(no sweep)";
  std::string s;
  for (size_t a = 0; a < config.sweep.size(); ++a) {
    s += (a ? ", " : "") + config.sweep[a].parameter + " = " + FormatValue(point.values[a]);
  }
  return s;
}

int MethodIndex(const ExperimentConfig& config, const std::string& id) {
  for (size_t m = 0; m < config.methods.size(); ++m) {
    if (config.methods[m].Id() == id) return static_cast<int>(m);
  }
  return -1;
}

int MetricsFrameFor(const ExperimentConfig& config, int frames) {
  return config.metrics_frame < 0 ? frames - 1 : config.metrics_frame;
}

std::string FormatValue(const nlohmann::json& value) {
  if (value.is_string()) return value.get<std::string>();
  return value.is_number_float() ? FormatDouble(value.get<double>()) : value.dump();
}

}  // namespace slt
