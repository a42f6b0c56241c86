#include "methods/trifocal_line_ekf/trifocal_line_ekf.h"

#include <gtest/gtest.h>

#include <string>

#include "common/json_reader.h"

namespace slt {
namespace {

nlohmann::json ResolvedOptions(const nlohmann::json& options) {
  return TrifocalLineEkfInfo().create(options, "test")->Options();
}

TEST(TrifocalLineEkf, PaperPresetIsTheFaithfulSetting) {
  const nlohmann::json paper = ResolvedOptions({{"preset", "paper"}});
  EXPECT_EQ(paper["filter"]["state"], "velocity");
  EXPECT_EQ(paper["filter"]["max_iterations"], 1);
  EXPECT_EQ(paper["filter"]["robust"], false);
  EXPECT_EQ(paper["measurement"]["residual"], "theta_lambda");
  EXPECT_EQ(paper["measurement"]["noise"], "fixed");
  EXPECT_EQ(paper["measurement"]["direction"], "current_to_reference");
  EXPECT_NE(paper, ResolvedOptions(nlohmann::json::object()));
}

TEST(TrifocalLineEkf, LongRunPresetIsTheSettingItNames) {
  // The options written out in the long-run results' "dense keyframes" rows.
  const nlohmann::json written = nlohmann::json::parse(R"({
    "filter": {"adaptive_noise": false, "adaptive_process_noise": true},
    "measurement": {"consider_structure": true, "endpoint_sigma_px": 1.0, "min_epipolar_extent_px": 3,
                    "refinement": {"enabled": true, "keyframe_interval": 5,
                                   "keyframe_min_distance_m": 0.005, "max_keyframes": 300}}})");
  const nlohmann::json preset = ResolvedOptions({{"preset", "long_run"}});
  EXPECT_EQ(preset, ResolvedOptions(written));
  EXPECT_NE(preset, ResolvedOptions(nlohmann::json::object()));
  // The file's own values override the preset's.
  const nlohmann::json overridden =
      ResolvedOptions({{"preset", "long_run"}, {"measurement", {{"refinement", {{"max_keyframes", 64}}}}}});
  EXPECT_EQ(overridden["measurement"]["refinement"]["max_keyframes"], 64);
  EXPECT_EQ(overridden["measurement"]["refinement"]["keyframe_interval"], 5);
}

TEST(TrifocalLineEkf, LongRunConsistentPresetIsTheSettingItNames) {
  // The options the *_placement configs wrote out before the preset existed, and the robust
  // start's directions.
  const nlohmann::json written = nlohmann::json::parse(R"({
    "preset": "long_run",
    "filter": {"min_accel_sigma_m": 2e-5, "robust_max_sigma": 0.05},
    "measurement": {"endpoint_sigma_px": 0.5773502691896258,
                    "refinement": {"pose_covariance": "report_placement", "carry_over": false}}})");
  const nlohmann::json preset = ResolvedOptions({{"preset", "long_run_consistent"}});
  EXPECT_EQ(preset, ResolvedOptions(written));
  EXPECT_NE(preset, ResolvedOptions({{"preset", "long_run"}}));
}

TEST(TrifocalLineEkf, UnknownPresetNamesTheKnownOnes) {
  try {
    TrifocalLineEkfInfo().create({{"preset", "fast"}}, "cfg.json");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("cfg.json: key 'preset': must be one of \"default\", \"paper\", \"long_run\", \"long_run_consistent\""),
              std::string::npos)
        << e.what();
  }
  const std::vector<OptionDoc> docs = TrifocalLineEkfInfo().list_options();
  ASSERT_FALSE(docs.empty());
  EXPECT_EQ(docs[0].key, "preset");
  EXPECT_EQ(docs[0].allowed, "default | paper | long_run | long_run_consistent");
}

}  // namespace
}  // namespace slt
