#include "methods/taylor_line_sfm/taylor_line_sfm_options.h"

#include <gtest/gtest.h>

#include "common/json_changes.h"

namespace slt {
namespace {

TEST(TaylorLineSfmOptions, EnumsAreReadByName) {
  // Numbers and flags are round-tripped for every registered tracker by the shared suite
  // (tests/tracker_suite_test.cc); the enum names are this schema's own.
  const nlohmann::json defaults = TaylorLineSfmOptionsSchema().ToJson(TaylorLineSfmOptions());
  EXPECT_EQ(defaults["loss"], "cauchy");
  EXPECT_EQ(defaults["linear_solver"], "dense_schur");
  for (const auto& [loss, expected] : std::vector<std::pair<std::string, SegmentLoss>>{
           {"none", SegmentLoss::kNone}, {"huber", SegmentLoss::kHuber}, {"cauchy", SegmentLoss::kCauchy}}) {
    TaylorLineSfmOptions o;
    JsonReader reader({{"loss", loss}, {"linear_solver", "sparse_schur"}}, "test");
    TaylorLineSfmOptionsSchema().Read(reader, &o);
    EXPECT_EQ(o.loss, expected) << loss;
    EXPECT_EQ(o.linear_solver, WindowLinearSolver::kSparseSchur);
    EXPECT_EQ(TaylorLineSfmOptionsSchema().ToJson(o)["loss"], loss);
  }
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
