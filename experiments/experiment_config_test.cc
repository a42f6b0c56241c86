#include "experiments/experiment_config.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "common/json_reader.h"
#include "common/random.h"
#include "common/source_tree.h"
#include "experiments/experiment_driver.h"
#include "methods/pose_tracker.h"

namespace slt {
namespace {

using nlohmann::json;

// The message of the ConfigError thrown when reading `j` (empty when it reads fine).
std::string ErrorOf(const json& j) {
  try {
    ExperimentConfigFromJson(j, "cfg.json");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(ExperimentConfig, EmptyConfigHasTheDefaults) {
  const ExperimentConfig c = ExperimentConfigFromJson(json::object(), "cfg.json");
  EXPECT_EQ(c.trials, 20);
  EXPECT_EQ(c.seed, 1u);
  EXPECT_EQ(c.metrics_frame, -1);
  EXPECT_TRUE(c.sweep.empty());
  EXPECT_FALSE(c.per_frame_curves);
  EXPECT_TRUE(c.plots.empty());
  EXPECT_EQ(c.title, c.name);
}

TEST(ExperimentConfig, AllIsEveryRegisteredTrackerButThePlumbing) {
  const ExperimentConfig c = ExperimentConfigFromJson({{"methods", "all"}}, "cfg.json");
  std::vector<std::string> ids;
  for (const MethodSpec& m : c.methods) ids.push_back(m.Id());
  EXPECT_EQ(ids, RegisteredTrackerNames(false));
  for (const MethodSpec& m : c.methods) EXPECT_FALSE(FindTracker(m.name).plumbing_only);
  EXPECT_FALSE(ids.empty());
}

TEST(ExperimentConfig, ExtraMethodsAreAppendedWithLabelsAndOptions) {
  const ExperimentConfig c = ExperimentConfigFromJson(
      {{"extra_methods", {{{"name", "trifocal_line_ekf"}, {"label", "EKF, paper"}, {"options", {{"preset", "paper"}}}},
                          "constant_pose"}}},
      "cfg.json");
  const size_t n = RegisteredTrackerNames(false).size();
  ASSERT_EQ(c.methods.size(), n + 2);
  EXPECT_EQ(c.methods[n].Id(), "EKF, paper");
  EXPECT_EQ(c.methods[n].options, json({{"preset", "paper"}}));
  EXPECT_EQ(c.methods[n + 1].Id(), "constant_pose");
}

TEST(ExperimentConfig, ErrorsNameTheFileAndTheKey) {
  EXPECT_EQ(ErrorOf({{"trails", 3}}), "cfg.json: key 'trails': unknown key");
  EXPECT_EQ(ErrorOf({{"trials", "many"}}).rfind("cfg.json: key 'trials': ", 0), 0u);
  EXPECT_EQ(ErrorOf({{"trials", 0}}), "cfg.json: key 'trials': must be >= 1");
  EXPECT_NE(ErrorOf({{"sweep", {{{"parameter", "noise.endpoint_px"}, {"values", 1}}}}}).find("key 'sweep[0].values'"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"sweep", {{{"parameter", "noise.endpoint_px"}, {"values", {1, 2}}, {"lable", "x"}}}}})
                .find("key 'sweep[0].lable': unknown key"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"methods", {"trifocal_line_ekf", "no_such_tracker"}}}).find("cfg.json: key 'methods[1]': unknown method"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"methods", {{{"name", "trifocal_line_ekf"}, {"options", {{"preset", "fast"}}}}}}})
                .find("cfg.json: key 'methods[0].options.preset'"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"methods", {{{"label", "x"}}}}}).find("key 'methods[0].name'"), std::string::npos);
  EXPECT_NE(ErrorOf({{"methods", {"trifocal_line_ekf", "trifocal_line_ekf"}}}).find("key 'methods': two methods have the id"),
            std::string::npos);
  EXPECT_EQ(ErrorOf({{"sweep", {{{"parameter", "noise.endpoint_px"}, {"values", {1, 2, 1}}}}}}),
            "cfg.json: key 'sweep[0].values[2]': duplicate value 1");
  EXPECT_EQ(ErrorOf({{"plots", {{{"kind", "methods"}, {"file", "a.png"}}, {{"kind", "methods"}, {"file", "a.png"}}}}}),
            "cfg.json: key 'plots[1].file': used twice");
  EXPECT_NE(ErrorOf({{"metrics_frame", 100}}).find("cfg.json: key 'metrics_frame': frame 100 does not exist"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"metrics_frame", -2}}).find("key 'metrics_frame'"), std::string::npos);
  EXPECT_NE(ErrorOf({{"plots", {{{"kind", "sweep"}, {"file", "a.png"}}}}}).find("key 'plots[0].kind'"), std::string::npos);
  EXPECT_NE(ErrorOf({{"plots", {{{"kind", "pie"}, {"file", "a.png"}}}}}).find("key 'plots[0].kind'"), std::string::npos);
  EXPECT_NE(ErrorOf({{"plots", {{{"kind", "methods"}, {"file", "a.png"}, {"statistic", "mode"}}}}})
                .find("key 'plots[0].statistic': must be"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"plots", {{{"kind", "trajectory"}, {"file", "a.png"}, {"paper", {{{"x", 1}, {"rot_err_deg", 1}}}}}}}})
                .find("key 'plots[0].paper': the paper's values are drawn on \"sweep\" and \"methods\" plots only"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"plots", {{{"kind", "methods"}, {"file", "a.png"}, {"paper", {{{"rot_err_deg", 1}}}}}}}})
                .find("key 'plots[0].paper[0].x': required"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"plots", {{{"kind", "methods"}, {"file", "a.png"}, {"paper", {{{"x", 1}, {"rot", 1}}}}}}}})
                .find("key 'plots[0].paper[0].rot': unknown key"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"table_metrics", {"rot_err_deg", "speed"}}}).find("key 'table_metrics[1]': unknown metric 'speed'"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"expect_better", {{{"better", "nobody"}, {"worse", "yu_point_ekf"}}}}}).find("key 'expect_better[0].better'"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"expect_better", {{{"better", "yu_point_ekf"}, {"worse", "trifocal_line_ekf"}, {"at", {{"frames", 3}}}}}}})
                .find("key 'expect_better[0].at'"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"expect_better", {{{"better", "yu_point_ekf"}, {"worse", "trifocal_line_ekf"}, {"metrics", {"ate"}}}}}})
                .find("key 'expect_better[0].metrics[0]': unknown metric 'ate'"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"expect_bounds", {{{"method", "nobody"}, {"metric", "nees"}, {"max", 8}}}}}).find("key 'expect_bounds[0].method'"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"expect_bounds", {{{"method", "yu_point_ekf"}, {"metric", "speed"}, {"max", 8}}}}})
                .find("key 'expect_bounds[0].metric': unknown metric 'speed'"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"expect_bounds", {{{"method", "yu_point_ekf"}, {"metric", "nees"}, {"max", 8}, {"at", {{"frames", 3}}}}}}})
                .find("key 'expect_bounds[0].at'"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"expect_bounds", {{{"method", "yu_point_ekf"}, {"metric", "nees"}}}}})
                .find("key 'expect_bounds[0].max': give max, min or both"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"expect_bounds", {{{"method", "yu_point_ekf"}, {"metric", "nees"}, {"min", 4}, {"max", 3}}}}})
                .find("key 'expect_bounds[0].max': below min"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"reference_metrics", {"ate_trans_m", "nees"}}})
                .find("key 'reference_metrics': 'nees' is not compared with references"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"reference_metrics", {"ate"}}}).find("key 'reference_metrics[0]': unknown metric 'ate'"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"reference_metrics", json::array()}}).find("key 'reference_metrics': at least one metric"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"name", "a/b"}}).find("key 'name'"), std::string::npos);
}

TEST(ExperimentConfig, SimulationErrorsNameTheSimulationKey) {
  EXPECT_NE(ErrorOf({{"simulation", {{"noise", {{"endpont_px", 1}}}}}}).find("cfg.json: key 'simulation.noise.endpont_px'"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"simulation", {{"seed", 3}}}}).find("cfg.json: key 'simulation.seed'"), std::string::npos);
  // A misspelt swept parameter is an unknown simulation key, reported with the sweep point.
  const std::string e = ErrorOf({{"sweep", {{{"parameter", "noise.endpont_px"}, {"values", {1, 2}}}}}});
  EXPECT_NE(e.find("cfg.json: key 'simulation.noise.endpont_px'"), std::string::npos) << e;
  EXPECT_NE(e.find("sweep point noise.endpont_px = 1"), std::string::npos) << e;
  // An invalid swept value.
  EXPECT_NE(ErrorOf({{"sweep", {{{"parameter", "frames"}, {"values", {10, 0}}}}}}).find("key 'simulation.frames'"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"sweep", {{{"parameter", "seed"}, {"values", {1, 2}}}}}}).find("key 'sweep[0].parameter'"),
            std::string::npos);
  // The metrics frame must exist at every sweep point.
  EXPECT_NE(ErrorOf({{"metrics_frame", 50}, {"sweep", {{{"parameter", "frames"}, {"values", {100, 40}}}}}})
                .find("key 'metrics_frame'"),
            std::string::npos);
}

TEST(ExperimentConfig, PlotsKeepTheirCaptionStatisticAndThePapersValues) {
  const json input = {{"sweep", {{{"parameter", "noise.endpoint_px"}, {"values", {0, 2.5}}}}},
                      {"plots",
                       {{{"kind", "sweep"},
                         {"file", "a.png"},
                         {"caption", "a line"},
                         {"statistic", "both"},
                         {"paper", {{{"x", 2.5}, {"rot_err_deg", 0.4}, {"trans_err_m", 0.01}}}}},
                        {{"kind", "methods"}, {"file", "b.png"}}}}};
  const ExperimentConfig c = ExperimentConfigFromJson(input, "cfg.json");
  ASSERT_EQ(c.plots.size(), 2u);
  EXPECT_EQ(c.plots[0].caption, "a line");
  EXPECT_EQ(c.plots[0].statistic, "both");
  ASSERT_EQ(c.plots[0].paper.size(), 1u);
  EXPECT_EQ(c.plots[0].paper[0].x, 2.5);
  EXPECT_EQ(c.plots[0].paper[0].rot_err_deg, 0.4);
  EXPECT_EQ(c.plots[0].paper[0].trans_err_m, 0.01);
  EXPECT_TRUE(c.plots[0].paper[0].upper_bound);
  EXPECT_EQ(c.plots[0].paper[0].label, "paper");
  EXPECT_EQ(c.plots[1].statistic, "mean");
  const json resolved = ExperimentConfigToJson(c);
  EXPECT_EQ(ExperimentConfigToJson(ExperimentConfigFromJson(resolved, "config.resolved.json")), resolved);
}

TEST(ExperimentConfig, ResolvedConfigReadsBackToTheSameConfig) {
  const json input = {{"name", "t"},
                      {"trials", 3},
                      {"seed", 9},
                      {"simulation", {{"frames", 30}, {"scene", {{"type", "room"}}}}},
                      {"sweep",
                       {{{"parameter", "noise.endpoint_px"}, {"values", {0, 1.5}}},
                        {{"parameter", "outliers.rate"}, {"values", {0, 0.1}}, {"label", "Outliers"}}}},
                      {"extra_methods", {{{"name", "trifocal_line_ekf"}, {"label", "paper"}, {"options", {{"preset", "paper"}}}}}},
                      {"metrics_frame", 20},
                      {"per_frame_curves", true},
                      {"save_trajectories", 1}};
  const ExperimentConfig c = ExperimentConfigFromJson(input, "cfg.json");
  const json resolved = ResolvedConfigJson(c);
  const ExperimentConfig back = ExperimentConfigFromJson(resolved, "config.resolved.json");
  EXPECT_EQ(ExperimentConfigToJson(back), ExperimentConfigToJson(c));
  // Defaults are filled in: the default plots, the tracker options, the per-point simulations.
  EXPECT_EQ(resolved["plots"].size(), 3u);
  ASSERT_EQ(resolved["resolved"]["methods"].size(), c.methods.size());
  EXPECT_TRUE(resolved["resolved"]["methods"][0]["options"].is_object());
  ASSERT_EQ(resolved["resolved"]["points"].size(), 4u);
  EXPECT_EQ(resolved["resolved"]["points"][3]["simulation"]["noise"]["endpoint_px"], 1.5);
  EXPECT_EQ(resolved["resolved"]["points"][3]["simulation"]["outliers"]["rate"], 0.1);
  // The room's scene-dependent defaults survive: the base simulation is kept as given.
  EXPECT_EQ(resolved["resolved"]["points"][0]["simulation"]["motion"]["type"], "loop");
}

TEST(Sweep, ExpandsEveryCombinationFirstAxisOutermost) {
  SweepAxis a{"frames", {10, 20}, "frames"};
  SweepAxis b{"noise.endpoint_px", {0.0, 1.0, 2.0}, "noise"};
  const std::vector<SweepPoint> points = ExpandSweep({a, b});
  ASSERT_EQ(points.size(), 6u);
  EXPECT_EQ(points[0].values, (std::vector<json>{10, 0.0}));
  EXPECT_EQ(points[2].values, (std::vector<json>{10, 2.0}));
  EXPECT_EQ(points[3].values, (std::vector<json>{20, 0.0}));
  EXPECT_EQ(ExpandSweep({}).size(), 1u);
  EXPECT_TRUE(ExpandSweep({})[0].values.empty());
}

TEST(Sweep, TrialSeedIsTheSameForEverySweepValueAndDiffersAcrossTrials) {
  const ExperimentConfig c = ExperimentConfigFromJson(
      {{"seed", 5}, {"sweep", {{{"parameter", "noise.endpoint_px"}, {"values", {0, 1, 2.5}}}}}}, "cfg.json");
  const std::vector<SweepPoint> points = ExpandSweep(c.sweep);
  for (int trial = 0; trial < 3; ++trial) {
    for (size_t p = 0; p < points.size(); ++p) {
      const SimulationConfig s = TrialSimulation(c, points[p], trial);
      EXPECT_EQ(s.seed, TrialSeed(5, trial));
      EXPECT_DOUBLE_EQ(s.noise.endpoint_px, points[p].values[0].get<double>());
    }
  }
  EXPECT_NE(TrialSimulation(c, points[0], 0).seed, TrialSimulation(c, points[0], 1).seed);
}

TEST(Sweep, MetricsFrameDefaultsToTheLastFrame) {
  ExperimentConfig c;
  EXPECT_EQ(MetricsFrameFor(c, 100), 99);
  c.metrics_frame = 10;
  EXPECT_EQ(MetricsFrameFor(c, 100), 10);
}

TEST(FormatValue, NumbersInShortestFormStringsAsIs) {
  EXPECT_EQ(FormatValue(json(0.1)), "0.1");
  EXPECT_EQ(FormatValue(json(2.0)), "2");
  EXPECT_EQ(FormatValue(json(40)), "40");
  EXPECT_EQ(FormatValue(json("room")), "room");
  EXPECT_EQ(FormatValue(json(true)), "true");
}

TEST(ExperimentConfig, DatasetsAreTheSweep) {
  const ExperimentConfig c = ExperimentConfigFromJson(
      {{"trials", 1},
       {"datasets", {{{"path", "data/kitti_00/"}}, {{"path", "x/euroc"}, {"label", "V1"}, {"end_frame", 20}}}},
       {"methods", {"trifocal_line_ekf"}}},
      "cfg.json");
  ASSERT_EQ(c.datasets.size(), 2u);
  EXPECT_EQ(c.datasets[0].label, "kitti_00");
  EXPECT_EQ(c.datasets[1].label, "V1");
  ASSERT_EQ(c.sweep.size(), 1u);
  EXPECT_EQ(c.sweep[0].parameter, "dataset");
  EXPECT_EQ(c.sweep[0].values, std::vector<json>({"kitti_00", "V1"}));
  // Round trip.
  const ExperimentConfig back = ExperimentConfigFromJson(ExperimentConfigToJson(c), "back.json");
  EXPECT_EQ(ExperimentConfigToJson(back), ExperimentConfigToJson(c));
}

TEST(ExperimentConfig, DatasetTrackerOptionsAreMergedOverTheMethodsOwn) {
  // A platform's options (KITTI's car: a velocity prior of metres per frame) reach the methods
  // that take them on that dataset only; the method's other options stay.
  const ExperimentConfig c = ExperimentConfigFromJson(
      {{"trials", 1},
       {"datasets",
        {{{"path", "kitti"}, {"tracker_options", {{"trifocal_line_ekf", {{"filter", {{"initial_velocity_sigma_m", 1.0}}}}}}}},
         {{"path", "euroc"}}}},
       {"methods",
        {{{"name", "trifocal_line_ekf"}, {"options", {{"filter", {{"min_features", 9}, {"initial_velocity_sigma_m", 0.1}}}}}},
         "taylor_line_sfm"}}},
      "cfg.json");
  const json on_kitti = MethodOptionsOn(c.methods[0], c.datasets[0]);
  EXPECT_EQ(on_kitti.at("filter").at("initial_velocity_sigma_m"), 1.0);
  EXPECT_EQ(on_kitti.at("filter").at("min_features"), 9);
  EXPECT_EQ(MethodOptionsOn(c.methods[0], c.datasets[1]), c.methods[0].options);
  EXPECT_EQ(MethodOptionsOn(c.methods[1], c.datasets[0]), c.methods[1].options);
  EXPECT_EQ(CreateTracker("trifocal_line_ekf", on_kitti)->Options().at("filter").at("initial_velocity_sigma_m"), 1.0);
  // Round trip.
  const ExperimentConfig back = ExperimentConfigFromJson(ExperimentConfigToJson(c), "back.json");
  EXPECT_EQ(ExperimentConfigToJson(back), ExperimentConfigToJson(c));
}

TEST(ExperimentConfig, DatasetErrorsNameTheKey) {
  const json one = {{{"path", "d"}}};
  EXPECT_EQ(ErrorOf({{"datasets", one}}), "cfg.json: key 'trials': must be 1 with \"datasets\" (a recorded sequence has no random draws)");
  EXPECT_EQ(ErrorOf({{"trials", 1}, {"datasets", json::array()}}),
            "cfg.json: key 'datasets': expected a non-empty array of {\"path\", ...}");
  EXPECT_EQ(ErrorOf({{"trials", 1}, {"datasets", {{{"label", "x"}}}}}), "cfg.json: key 'datasets[0].path': missing: the sequence folder");
  EXPECT_NE(ErrorOf({{"trials", 1}, {"datasets", {{{"path", "d"}, {"layout", "tum"}}}}}).find("key 'datasets[0].layout'"),
            std::string::npos);
  EXPECT_EQ(ErrorOf({{"trials", 1}, {"datasets", {{{"path", "d"}, {"pth", "d"}}}}}), "cfg.json: key 'datasets[0].pth': unknown key");
  EXPECT_EQ(ErrorOf({{"trials", 1}, {"datasets", {{{"path", "a/d"}}, {{"path", "b/d"}}}}}),
            "cfg.json: key 'datasets[1].label': 'd' used twice");
  EXPECT_EQ(ErrorOf({{"trials", 1}, {"datasets", one}, {"simulation", json::object()}}),
            "cfg.json: key 'simulation': not with \"datasets\" (a run is on recorded or on simulated data)");
  EXPECT_EQ(ErrorOf({{"trials", 1}, {"datasets", one}, {"sweep", {{{"parameter", "noise.endpoint_px"}, {"values", {1}}}}}}),
            "cfg.json: key 'sweep': not with \"datasets\" (the datasets are the sweep)");
  EXPECT_EQ(ErrorOf({{"trials", 1}, {"datasets", one}, {"metrics_frame", 3}}),
            "cfg.json: key 'metrics_frame': must be \"last\" with \"datasets\"");
  EXPECT_NE(ErrorOf({{"trials", 1}, {"datasets", one}, {"frontend", {{"detektion", 1}}}}).find("cfg.json: key 'frontend.detektion'"),
            std::string::npos);
  EXPECT_NE(ErrorOf({{"trials", 1}, {"datasets", {{{"path", "d"}, {"tracker_options", {{"trifocal_ekf", json::object()}}}}}}})
                .find("cfg.json: key 'datasets[0].tracker_options': unknown method 'trifocal_ekf'"),
            std::string::npos);
  EXPECT_EQ(ErrorOf({{"trials", 1},
                     {"methods", {"trifocal_line_ekf"}},
                     {"datasets", {{{"path", "d"}, {"tracker_options", {{"trifocal_line_ekf", {{"filter", {{"initial_velocity_sigma_m", -1}}}}}}}}}}}),
            "cfg.json: key 'datasets[0].tracker_options.trifocal_line_ekf.filter.initial_velocity_sigma_m': must be > 0");
}

// The configs users have written keep loading, and every committed config.resolved.json reads
// back to the same values (its "resolved" section aside): the schema writes what the hand-written
// writer wrote.
// Every value of `written` stands in `rewritten` at the same place: objects key by key, arrays
// element by element (same length); `rewritten` may have more keys in an object.
void ExpectWrittenKeptIn(const json& written, const json& rewritten, const std::string& where) {
  if (written.is_object() && rewritten.is_object()) {
    for (const auto& [key, value] : written.items()) {
      if (!rewritten.contains(key)) {
        ADD_FAILURE() << where << "." << key << " is not written back";
        continue;
      }
      ExpectWrittenKeptIn(value, rewritten[key], where + "." + key);
    }
  } else if (written.is_array() && rewritten.is_array() && written.size() == rewritten.size()) {
    for (size_t i = 0; i < written.size(); ++i) ExpectWrittenKeptIn(written[i], rewritten[i], IndexedKey(where, i));
  } else {
    EXPECT_EQ(rewritten, written) << where;
  }
}

TEST(ExperimentConfig, EveryConfigLoadsAndEveryCommittedResolvedConfigRoundTrips) {
  const std::vector<std::string> configs = AvailableConfigs();
  ASSERT_FALSE(configs.empty());
  for (const std::string& name : configs) {
    EXPECT_NO_THROW(ReadExperimentConfig(FindConfigFile(name))) << name;
  }
  int resolved_files = 0;
  const json defaults = ExperimentConfigToJson(ExperimentConfig());
  for (const char* folder : {"results", "results/reference"}) {
    for (const auto& entry : std::filesystem::directory_iterator(SourceDir() + "/" + folder)) {
      const std::string path = (entry.path() / "config.resolved.json").string();
      if (!std::filesystem::exists(path)) continue;
      json written = ReadJsonFile(path);
      written.erase("resolved");
      const json rewritten = ExperimentConfigToJson(ExperimentConfigFromJson(written, path));
      // Keys added since a result was made are written with their defaults (at the top level:
      // the defaults of an empty config); every written value is read back the same, and the
      // rewrite reads back to itself.
      ExpectWrittenKeptIn(written, rewritten, path);
      for (const auto& [key, value] : rewritten.items()) {
        if (!written.contains(key)) {
          EXPECT_EQ(value, defaults.at(key)) << path << " " << key;
        }
      }
      EXPECT_EQ(ExperimentConfigToJson(ExperimentConfigFromJson(rewritten, path)), rewritten) << path;
      ++resolved_files;
    }
  }
  EXPECT_GT(resolved_files, 10);
}

}  // namespace
}  // namespace slt
