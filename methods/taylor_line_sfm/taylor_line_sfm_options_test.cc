#include "methods/taylor_line_sfm/taylor_line_sfm_options.h"

#include <gtest/gtest.h>

#include "common/json_changes.h"

namespace slt {
namespace {

TEST(TaylorLineSfmOptions, JsonRoundTripKeepsEveryField) {
  // Every field changed from its default to another valid value: a field that the schema reads
  // or writes wrongly comes back at its default and breaks the equality.
  const OptionSchema<TaylorLineSfmOptions>& schema = TaylorLineSfmOptionsSchema();
  const nlohmann::json defaults = schema.ToJson(TaylorLineSfmOptions());
  nlohmann::json changed = defaults;
  for (auto& [key, value] : changed.items()) {
    if (!value.is_string()) value = ChangedJsonValues(value).front();
  }
  changed["loss"] = "huber";
  changed["linear_solver"] = "sparse_schur";
  ASSERT_EQ(changed.size(), 15u) << "a field was added: extend this test if it needs a special value";
  for (const auto& [key, value] : changed.items()) EXPECT_NE(value, defaults[key]) << key;

  TaylorLineSfmOptions read;
  JsonReader reader(changed, "test");
  schema.Read(reader, &read);
  reader.RejectUnknownKeys();
  EXPECT_EQ(schema.ToJson(read), changed);
}

TEST(TaylorLineSfmOptions, ErrorsNameTheFileAndTheKey) {
  for (const auto& [key, value] : std::vector<std::pair<std::string, nlohmann::json>>{
           {"window_frames", 1}, {"window_frames", -1}, {"sigma_px", 0.0}, {"loss", "l2"},
           {"linear_solver", "dense_qr"}, {"max_iterations", 0}, {"threads", 0},
           {"lost_velocity_decay", 1.5}, {"min_plane_angle_deg", 90.0}, {"outlier_rms_sigma", -1.0}}) {
    const std::string message = ConfigErrorOf([&, key = key, value = value] {
      TaylorLineSfmOptions o;
      JsonReader reader({{key, value}}, "tracker.json");
      TaylorLineSfmOptionsSchema().Read(reader, &o);
    });
    EXPECT_NE(message.find("tracker.json"), std::string::npos) << key << " = " << value << ": " << message;
    EXPECT_NE(message.find("'" + key + "'"), std::string::npos) << key << " = " << value << ": " << message;
  }
  // The batch form.
  TaylorLineSfmOptions o;
  JsonReader reader({{"window_frames", 0}}, "tracker.json");
  TaylorLineSfmOptionsSchema().Read(reader, &o);
  EXPECT_EQ(o.window_frames, 0);
}

}  // namespace
}  // namespace slt
