#include "experiments/experiment_config.h"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <set>

#include "common/json_reader.h"
#include "common/options.h"
#include "common/random.h"
#include "experiments/trial_result.h"
#include "frontend/frontend_options.h"
#include "frontend/image_sequence.h"
#include "methods/pose_tracker.h"

namespace slt {
namespace {

std::string Indexed(const std::string& key, size_t i) { return key + "[" + std::to_string(i) + "]"; }

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

MethodSpec ReadMethod(const nlohmann::json& j, const std::string& where, const std::string& key) {
  MethodSpec method;
  if (j.is_string()) {
    method.name = j.get<std::string>();
  } else if (j.is_object()) {
    JsonReader reader(j, where, key);
    reader.Get("name", &method.name);
    reader.Get("label", &method.label);
    if (const nlohmann::json* options = reader.Find("options")) {
      if (!options->is_object()) reader.Fail("options", std::string("expected an object, got ") + options->type_name());
      method.options = *options;
    }
    reader.RejectUnknownKeys();
    if (method.name.empty()) reader.Fail("name", "missing: the registered tracker name");
  } else {
    ThrowOptionError(where, "", key, std::string("expected a tracker name or {\"name\": ..}, got ") + j.type_name());
  }
  try {
    FindTracker(method.name);
  } catch (const std::invalid_argument& e) {
    ThrowOptionError(where, "", key, e.what());
  }
  if (method.label.empty()) method.label = method.name;
  // Invalid tracker options fail here, naming the key, rather than in the middle of a run.
  try {
    CreateTracker(method.name, method.options, where);
  } catch (const ConfigError& e) {
    RethrowUnder(e, where, j.is_object() ? key + ".options" : key);
  }
  return method;
}

std::vector<MethodSpec> AllMethods() {
  std::vector<MethodSpec> methods;
  for (const TrackerInfo& info : RegisteredTrackers()) {
    if (info.plumbing_only) continue;
    MethodSpec m;
    m.name = info.name;
    m.label = info.name;
    methods.push_back(m);
  }
  return methods;
}

std::vector<MethodSpec> ReadMethodList(JsonReader& reader, const std::string& key, bool allow_all) {
  const nlohmann::json* v = reader.Find(key);
  if (v == nullptr) return allow_all ? AllMethods() : std::vector<MethodSpec>{};
  if (allow_all && v->is_string() && v->get<std::string>() == "all") return AllMethods();
  if (!v->is_array()) reader.Fail(key, std::string(allow_all ? "expected \"all\" or " : "expected ") + "an array of methods");
  std::vector<MethodSpec> methods;
  for (size_t i = 0; i < v->size(); ++i) methods.push_back(ReadMethod((*v)[i], reader.where(), Indexed(reader.KeyPath(key), i)));
  return methods;
}

SweepAxis ReadAxis(const nlohmann::json& j, const std::string& where, const std::string& key) {
  JsonReader reader(j, where, key);
  SweepAxis axis;
  reader.Get("parameter", &axis.parameter);
  reader.Get("label", &axis.label);
  const nlohmann::json* values = reader.Find("values");
  reader.RejectUnknownKeys();
  if (axis.parameter.empty()) reader.Fail("parameter", "missing: a dotted key of the simulation config");
  if (axis.parameter == "seed") reader.Fail("parameter", "'seed' cannot be swept (trials set it; use the top-level 'seed' or 'trials')");
  if (values == nullptr || !values->is_array() || values->empty()) reader.Fail("values", "expected a non-empty array");
  for (size_t i = 0; i < values->size(); ++i) {
    if (!IsScalar((*values)[i])) reader.Fail(Indexed("values", i), "expected a number, string or boolean");
    for (size_t k = 0; k < i; ++k) {
      if ((*values)[k] == (*values)[i]) reader.Fail(Indexed("values", i), "duplicate value " + (*values)[i].dump());
    }
    axis.values.push_back((*values)[i]);
  }
  if (axis.label.empty()) axis.label = axis.parameter;
  return axis;
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
          .Check("rot_err_deg", [](const R& v) {
            return v.rot_err_deg < 0.0 && v.trans_err_m < 0.0 ? "give rot_err_deg, trans_err_m or both (>= 0)" : "";
          });
  return schema;
}

void ReadPaperValues(JsonReader& r, PlotSpec* p) {
  const nlohmann::json* paper = r.Find("paper");
  if (!paper) return;
  if (!paper->is_array()) r.Fail("paper", "expected an array of {\"x\", \"rot_err_deg\", \"trans_err_m\"} objects");
  p->paper.clear();
  for (size_t i = 0; i < paper->size(); ++i) {
    JsonReader value_reader((*paper)[i], r.where(), Indexed(r.KeyPath("paper"), i));
    if (!value_reader.Find("x")) value_reader.Fail("x", "required: the value of the swept parameter (any number on a \"methods\" plot)");
    ReportedValue value;
    ReportedValueSchema().ReadFields(value_reader, &value);
    value_reader.RejectUnknownKeys();
    ReportedValueSchema().Validate(value, value_reader.where(), value_reader.path());
    p->paper.push_back(value);
  }
}

nlohmann::json PaperValuesToJson(const PlotSpec& p) {
  nlohmann::json paper = nlohmann::json::array();
  for (const ReportedValue& v : p.paper) paper.push_back(ReportedValueSchema().ToJson(v));
  return paper;
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
          .Custom("paper", ReadPaperValues, PaperValuesToJson, "array of {x, rot_err_deg, trans_err_m, upper_bound, label}",
                  "sweep: the paper's values drawn as black triangles; methods: as dashed lines")
          .Check("file", [](const P& p) {
            return p.file.size() < 5 || p.file.substr(p.file.size() - 4) != ".png" || p.file.find('/') != std::string::npos
                       ? "expected a file name ending in .png (no directory)"
                       : "";
          });
  return schema;
}

PlotSpec ReadPlot(const nlohmann::json& j, const std::string& where, const std::string& key) {
  JsonReader reader(j, where, key);
  PlotSpec plot;
  PlotSchema().Read(reader, &plot);
  reader.RejectUnknownKeys();
  return plot;
}

std::vector<PlotSpec> DefaultPlots(const ExperimentConfig& c) {
  std::vector<PlotSpec> plots;
  PlotSpec p;
  if (c.sweep.size() == 1 && c.datasets.empty()) {  // datasets: categories, no sweep curve
    p.kind = "sweep";
    p.file = c.name + ".png";
    plots.push_back(p);
  } else if (c.sweep.size() == 2) {
    p.kind = "grid";
    p.file = c.name + ".png";
    plots.push_back(p);
  }
  if (c.per_frame_curves) {
    p = PlotSpec();
    p.kind = "curves";
    p.file = c.name + "_curves.png";
    plots.push_back(p);
  }
  if (c.save_trajectories > 0) {
    p = PlotSpec();
    p.kind = "trajectory";
    p.file = c.name + "_trajectory.png";
    plots.push_back(p);
  }
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

// Reads a simulation JSON; errors read "<where>: key 'simulation.<key>': <reason>" (with
// " (at sweep point <at>)" appended when `at` is not empty).
SimulationConfig ParseSimulation(const nlohmann::json& sim, const std::string& where, const std::string& at) {
  try {
    SimulationConfig config = SimulationConfigFromJson(sim, where);
    config.Check(where);
    return config;
  } catch (const ConfigError& e) {
    RethrowUnder(e, where, "simulation", at.empty() ? "" : " (at sweep point " + at + ")");
  }
}

OrderingCheck ReadOrdering(const ExperimentConfig& c, const nlohmann::json& j, const std::string& where,
                           const std::string& key) {
  JsonReader reader(j, where, key);
  OrderingCheck o;
  reader.Get("better", &o.better).Get("worse", &o.worse);
  if (const nlohmann::json* at = reader.Find("at")) o.at = *at;
  reader.RejectUnknownKeys();
  for (const char* side : {"better", "worse"}) {
    const std::string& id = std::string(side) == "better" ? o.better : o.worse;
    bool found = false;
    for (const MethodSpec& m : c.methods) found = found || m.Id() == id;
    if (!found) reader.Fail(side, "'" + id + "' is not the id of a method of this config");
  }
  if (!o.at.is_object()) reader.Fail("at", "expected an object {\"<swept parameter>\": value}");
  for (const auto& [parameter, value] : o.at.items()) {
    bool found = false;
    for (const SweepAxis& a : c.sweep) {
      found = found || (a.parameter == parameter && std::find(a.values.begin(), a.values.end(), value) != a.values.end());
    }
    if (!found) reader.Fail("at", parameter + " = " + value.dump() + " is not a value of a swept parameter");
  }
  return o;
}

nlohmann::json ToJson(const MethodSpec& m) {
  return {{"name", m.name}, {"label", m.label}, {"options", m.options}};
}

nlohmann::json ToJson(const SweepAxis& a) {
  return {{"parameter", a.parameter}, {"values", a.values}, {"label", a.label}};
}

DatasetSpec ReadDataset(const nlohmann::json& j, const std::string& where, const std::string& key) {
  if (!j.is_object()) ThrowOptionError(where, "", key, std::string("expected {\"path\": ..}, got ") + j.type_name());
  JsonReader reader(j, where, key);
  DatasetSpec d;
  reader.Get("path", &d.path).Get("label", &d.label).Get("layout", &d.layout);
  reader.Get("first_frame", &d.first_frame).Get("end_frame", &d.end_frame).Get("ground_truth", &d.ground_truth);
  reader.RejectUnknownKeys();
  if (d.path.empty()) reader.Fail("path", "missing: the sequence folder");
  try {
    DatasetLayoutFromName(d.layout);
  } catch (const std::invalid_argument& e) {
    reader.Fail("layout", e.what());
  }
  if (d.first_frame < 0) reader.Fail("first_frame", "must be >= 0");
  if (d.end_frame != -1 && d.end_frame <= d.first_frame) reader.Fail("end_frame", "must be > first_frame, or -1 (to the end)");
  if (d.label.empty()) d.label = std::filesystem::path(d.path).lexically_normal().filename().string();
  if (d.label.empty()) d.label = std::filesystem::path(d.path).lexically_normal().parent_path().filename().string();
  return d;
}

nlohmann::json ToJson(const DatasetSpec& d) {
  return {{"path", d.path},         {"label", d.label},         {"layout", d.layout},
          {"first_frame", d.first_frame}, {"end_frame", d.end_frame}, {"ground_truth", d.ground_truth}};
}

nlohmann::json ToJson(const OrderingCheck& o) { return {{"better", o.better}, {"worse", o.worse}, {"at", o.at}}; }

nlohmann::json ToJson(const PlotSpec& p) { return PlotSchema().ToJson(p); }

}  // namespace

ExperimentConfig ExperimentConfigFromJson(const nlohmann::json& j, const std::string& where) {
  JsonReader reader(j, where);
  ExperimentConfig c;
  reader.Get("name", &c.name).Get("title", &c.title).Get("trials", &c.trials).Get("seed", &c.seed);
  if (c.name.empty() || c.name.find_first_of("/\\ ") != std::string::npos || c.name[0] == '.') {
    reader.Fail("name", "expected a non-empty name without '/', '\\' or spaces (it names the output directory)");
  }
  if (c.title.empty()) c.title = c.name;
  if (c.trials < 1) reader.Fail("trials", "must be >= 1");

  if (const nlohmann::json* sim = reader.Find("simulation")) {
    if (!sim->is_object()) reader.Fail("simulation", std::string("expected an object, got ") + sim->type_name());
    c.simulation = *sim;
  }
  if (const nlohmann::json* datasets = reader.Find("datasets")) {
    if (!datasets->is_array() || datasets->empty()) reader.Fail("datasets", "expected a non-empty array of {\"path\", ...}");
    for (size_t i = 0; i < datasets->size(); ++i) c.datasets.push_back(ReadDataset((*datasets)[i], where, Indexed("datasets", i)));
    for (size_t i = 0; i < c.datasets.size(); ++i) {
      for (size_t k = 0; k < i; ++k) {
        if (c.datasets[k].label == c.datasets[i].label) {
          ThrowOptionError(where, Indexed("datasets", i), "label", "'" + c.datasets[i].label + "' used twice");
        }
      }
    }
    if (reader.Has("simulation")) reader.Fail("simulation", "not with \"datasets\" (a run is on recorded or on simulated data)");
    if (c.trials != 1) reader.Fail("trials", "must be 1 with \"datasets\" (a recorded sequence has no random draws)");
    SweepAxis axis;
    axis.parameter = axis.label = "dataset";
    for (const DatasetSpec& d : c.datasets) axis.values.push_back(d.label);
    c.sweep.push_back(axis);
    // config.json writes this axis (for the plots); reading it back, it must be just that.
    if (const nlohmann::json* sweep = reader.Find("sweep")) {
      if (*sweep != nlohmann::json::array({ToJson(axis)})) {
        reader.Fail("sweep", "not with \"datasets\" (the datasets are the sweep)");
      }
    }
  }
  if (const nlohmann::json* frontend = reader.Find("frontend")) {
    if (!frontend->is_object()) reader.Fail("frontend", std::string("expected an object, got ") + frontend->type_name());
    c.frontend = *frontend;
    try {
      FrontEndOptionsFromJson(c.frontend, where);
    } catch (const ConfigError& e) {
      // "frontend: key 'x': reason" -> "<where>: key 'frontend.x': reason".
      RethrowUnder(e, where, "frontend", "");
    }
  }
  if (c.simulation.contains("seed")) {
    ThrowOptionError(where, "simulation", "seed", "set by the experiment (trial k uses TrialSeed(seed, k)); use the top-level 'seed'");
  }
  ParseSimulation(c.simulation, where, "");

  if (const nlohmann::json* sweep = c.datasets.empty() ? reader.Find("sweep") : nullptr) {
    if (!sweep->is_array()) reader.Fail("sweep", "expected an array of {\"parameter\", \"values\"}");
    if (sweep->size() > 2) reader.Fail("sweep", "at most 2 swept parameters");
    for (size_t i = 0; i < sweep->size(); ++i) c.sweep.push_back(ReadAxis((*sweep)[i], where, Indexed("sweep", i)));
    if (c.sweep.size() == 2 && c.sweep[0].parameter == c.sweep[1].parameter) {
      reader.Fail("sweep[1].parameter", "the same parameter as sweep[0]");
    }
  }

  c.methods = ReadMethodList(reader, "methods", true);
  for (MethodSpec& m : ReadMethodList(reader, "extra_methods", false)) c.methods.push_back(m);
  if (c.methods.empty()) reader.Fail("methods", "no method to run");
  for (size_t i = 0; i < c.methods.size(); ++i) {
    for (size_t k = 0; k < i; ++k) {
      if (c.methods[k].label == c.methods[i].label) {
        reader.Fail("methods", "two methods have the id '" + c.methods[i].label +
                                   "' (give the second a distinct \"label\")");
      }
    }
  }

  if (const nlohmann::json* mf = reader.Find("metrics_frame")) {
    if (mf->is_string() && mf->get<std::string>() == "last") {
      c.metrics_frame = -1;
    } else if (mf->is_number_integer() && mf->get<long long>() >= 0 && mf->get<long long>() < (1LL << 30)) {
      c.metrics_frame = mf->get<int>();
    } else {
      reader.Fail("metrics_frame", "expected a frame index >= 0 or \"last\"");
    }
  }
  reader.Get("per_frame_curves", &c.per_frame_curves).Get("save_trajectories", &c.save_trajectories);
  if (c.save_trajectories < 0) reader.Fail("save_trajectories", "must be >= 0");
  c.save_trajectories = std::min(c.save_trajectories, c.trials);
  reader.Get("table_metrics", &c.table_metrics);
  for (size_t i = 0; i < c.table_metrics.size(); ++i) {
    if (c.table_metrics[i] == "time_us") c.table_metrics[i] = TrialMetricName(kTimeMeanUs);
    if (TrialMetricFromName(c.table_metrics[i]) < 0) {
      std::string known;
      for (int m = 0; m < kNumTrialMetrics; ++m) known += std::string(" ") + TrialMetricName(m);
      reader.Fail(Indexed("table_metrics", i), "unknown metric '" + c.table_metrics[i] + "' (known:" + known + ")");
    }
  }

  if (const nlohmann::json* plots = reader.Find("plots")) {
    if (!plots->is_array()) reader.Fail("plots", "expected an array of plot objects");
    for (size_t i = 0; i < plots->size(); ++i) c.plots.push_back(ReadPlot((*plots)[i], where, Indexed("plots", i)));
  } else {
    c.plots = DefaultPlots(c);
  }
  for (size_t i = 0; i < c.plots.size(); ++i) {
    CheckPlot(c, c.plots[i], where, Indexed("plots", i));
    if (c.plots[i].title.empty()) c.plots[i].title = c.title;
    for (size_t k = 0; k < i; ++k) {
      if (c.plots[k].file == c.plots[i].file) ThrowOptionError(where, Indexed("plots", i), "file", "used twice");
    }
  }
  if (const nlohmann::json* pairs = reader.Find("expect_better")) {
    if (!pairs->is_array()) reader.Fail("expect_better", "expected an array of {\"better\", \"worse\", \"at\"}");
    for (size_t i = 0; i < pairs->size(); ++i) c.expect_better.push_back(ReadOrdering(c, (*pairs)[i], where, Indexed("expect_better", i)));
  }
  reader.Find("resolved");  // output only (ResolvedConfigJson): ignored on input
  reader.RejectUnknownKeys();

  if (!c.datasets.empty()) {
    // Frame counts are known when the datasets are opened; errors are read at the last frame.
    if (c.metrics_frame != -1) reader.Fail("metrics_frame", "must be \"last\" with \"datasets\"");
    return c;
  }
  // Every sweep point must give a valid simulation, and the metrics frame must exist in it.
  const std::vector<SweepPoint> points = ExpandSweep(c.sweep);
  for (const SweepPoint& point : points) {
    nlohmann::json sim = c.simulation;
    for (size_t a = 0; a < c.sweep.size(); ++a) {
      try {
        SetDottedKey(&sim, c.sweep[a].parameter, point.values[a]);
      } catch (const std::invalid_argument& e) {
        ThrowOptionError(where, Indexed("sweep", a), "parameter", e.what());
      }
    }
    std::string at;
    for (size_t a = 0; a < c.sweep.size(); ++a) at += (a ? ", " : "") + c.sweep[a].parameter + " = " + FormatValue(point.values[a]);
    const SimulationConfig config = ParseSimulation(sim, where, at);
    if (c.metrics_frame >= config.frames) {
      reader.Fail("metrics_frame", "frame " + std::to_string(c.metrics_frame) + " does not exist in a sequence of " +
                                       std::to_string(config.frames) + " frames (frames count from 0)");
    }
  }
  return c;
}

ExperimentConfig ReadExperimentConfig(const std::string& path) {
  return ExperimentConfigFromJson(ReadJsonFile(path), path);
}

nlohmann::json ExperimentConfigToJson(const ExperimentConfig& c) {
  nlohmann::json j;
  j["name"] = c.name;
  j["title"] = c.title;
  j["trials"] = c.trials;
  j["seed"] = c.seed;
  const auto array_of = [](const auto& items) {
    nlohmann::json array = nlohmann::json::array();
    for (const auto& item : items) array.push_back(ToJson(item));
    return array;
  };
  if (c.datasets.empty()) {
    j["simulation"] = c.simulation;
  } else {
    j["datasets"] = array_of(c.datasets);
    j["frontend"] = c.frontend;
  }
  j["sweep"] = array_of(c.sweep);
  j["methods"] = array_of(c.methods);
  if (c.metrics_frame < 0) {
    j["metrics_frame"] = "last";
  } else {
    j["metrics_frame"] = c.metrics_frame;
  }
  j["per_frame_curves"] = c.per_frame_curves;
  j["save_trajectories"] = c.save_trajectories;
  j["table_metrics"] = c.table_metrics;
  j["plots"] = array_of(c.plots);
  j["expect_better"] = array_of(c.expect_better);
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
      resolved["points"].push_back({{"point", p}, {"values", values}, {"dataset", ToJson(c.datasets[p])}});
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
        SweepPoint q = p;
        q.values.push_back(v);
        next.push_back(q);
      }
    }
    points = next;
  }
  return points;
}

void SetDottedKey(nlohmann::json* object, const std::string& dotted_key, const nlohmann::json& value) {
  nlohmann::json* node = object;
  size_t start = 0;
  while (true) {
    const size_t dot = dotted_key.find('.', start);
    const std::string part = dotted_key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (part.empty()) throw std::invalid_argument("malformed dotted key '" + dotted_key + "'");
    if (!node->is_object()) {
      throw std::invalid_argument("'" + dotted_key.substr(0, start ? start - 1 : 0) + "' is not an object");
    }
    if (dot == std::string::npos) {
      (*node)[part] = value;
      return;
    }
    if (!node->contains(part)) (*node)[part] = nlohmann::json::object();
    node = &(*node)[part];
    start = dot + 1;
  }
}

SimulationConfig TrialSimulation(const ExperimentConfig& config, const SweepPoint& point, int trial) {
  nlohmann::json sim = config.simulation;
  for (size_t a = 0; a < config.sweep.size(); ++a) SetDottedKey(&sim, config.sweep[a].parameter, point.values[a]);
  SimulationConfig s = SimulationConfigFromJson(sim, config.name + ": simulation");
  s.seed = TrialSeed(config.seed, static_cast<std::uint64_t>(trial));
  return s;
}

int MetricsFrameFor(const ExperimentConfig& config, int frames) {
  return config.metrics_frame < 0 ? frames - 1 : config.metrics_frame;
}

std::string FormatValue(const nlohmann::json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_number_float()) {
    char buffer[64];
    const auto r = std::to_chars(buffer, buffer + sizeof(buffer), value.get<double>());
    return std::string(buffer, r.ptr);
  }
  return value.dump();
}

}  // namespace slt
