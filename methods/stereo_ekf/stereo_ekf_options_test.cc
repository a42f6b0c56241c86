#include "methods/stereo_ekf/stereo_ekf_options.h"

#include <gtest/gtest.h>

#include "common/json_changes.h"

namespace slt {
namespace {

TEST(StereoEkfOptions, GateThresholdComesFromTheProbability) {
  StereoEkfOptions o;
  o.gate_probability = 0.99;
  EXPECT_NEAR(o.GateThreshold(), 13.276704, 1e-5);
  // A line measured by one transfer only has two residual rows: chi-square(2).
  EXPECT_NEAR(o.GateThreshold(2), 9.210340, 1e-5);
}

TEST(StereoEkfOptions, JsonRoundTripKeepsEveryField) {
  // Every field changed from its default to another valid value: a field that ReadStereoEkfOptions
  // or StereoEkfOptionsToJson forgets comes back at its default and breaks the equality.
  const nlohmann::json defaults = StereoEkfOptionsToJson(StereoEkfOptions());
  nlohmann::json changed = defaults;
  for (auto& [key, value] : changed.items()) {
    if (!value.is_string()) value = ChangedJsonValues(value).front();
  }
  changed["state"] = "velocity";
  changed["integration"] = "first_order";
  changed["count_features"] = "gated";
  ASSERT_EQ(changed.size(), 27u) << "a field was added: extend this test if it needs a special value";
  for (const auto& [key, value] : changed.items()) EXPECT_NE(value, defaults[key]) << key;

  StereoEkfOptions read;
  JsonReader reader(changed, "test");
  ReadStereoEkfOptions(reader, &read);  // also checks the values
  reader.RejectUnknownKeys();           // every written key is a known one
  EXPECT_EQ(StereoEkfOptionsToJson(read), changed);
}

TEST(StereoEkfOptions, CheckNamesTheBadKey) {
  StereoEkfOptions o;
  o.max_iterations = 0;
  try {
    o.Check("tracker.json", "filter");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("tracker.json: key 'filter.max_iterations'"), std::string::npos) << e.what();
  }
  StereoEkfOptions bad_tolerance;
  bad_tolerance.iteration_tolerance = -1.0;
  EXPECT_THROW(bad_tolerance.Check(), ConfigError);
  StereoEkfOptions too_few;
  too_few.min_features = 1;
  EXPECT_THROW(too_few.Check(), ConfigError);
  // A refresh that would switch to a pair holding fewer features than the reference has left.
  StereoEkfOptions shrinking;
  shrinking.refresh_gain = 0.5;
  EXPECT_THROW(shrinking.Check(), ConfigError);
  // The adapted process noise's floor above its ceiling: an error only when it is adapted.
  StereoEkfOptions inverted;
  inverted.min_accel_sigma_m = 2.0 * inverted.accel_sigma_m;
  EXPECT_NO_THROW(inverted.Check());
  inverted.adaptive_process_noise = true;
  try {
    inverted.Check("tracker.json", "filter");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'filter.min_accel_sigma_m'"), std::string::npos) << e.what();
  }
}

TEST(StereoEkfOptions, WrongJsonTypeOrModeIsAnError) {
  StereoEkfOptions o;
  JsonReader reader(nlohmann::json{{"max_iterations", "three"}}, "tracker.json", "filter");
  EXPECT_THROW(ReadStereoEkfOptions(reader, &o), ConfigError);
  JsonReader bad_state(nlohmann::json{{"state", "pose"}}, "tracker.json", "filter");
  try {
    ReadStereoEkfOptions(bad_state, &o);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "tracker.json: key 'filter.state': must be \"velocity\" or \"pose_velocity\"");
  }
}

TEST(StereoEkfOptions, PaperPresetIsThePapersFilter) {
  StereoEkfOptions o;
  ApplyPaperPreset(&o);
  EXPECT_EQ(o.state, FilterState::kVelocity);
  EXPECT_EQ(o.max_iterations, 1);
  EXPECT_FALSE(o.robust);
  EXPECT_FALSE(o.adaptive_noise);
  EXPECT_EQ(o.count_features, FeatureCount::kGated);
  EXPECT_EQ(o.lost.lost_velocity_decay, 1.0);  // the paper keeps predicting at constant velocity
  EXPECT_NO_THROW(o.Check());
}

}  // namespace
}  // namespace slt
