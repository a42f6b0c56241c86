// Accuracy regressions of the trifocal-line EKF on the paper's protocol (Sec. 5.1): 40 random
// lines, 100 frames, per-frame motion up to 1.2 deg and 0.010 m, error of the pose at frame 100,
// mean over 20 trials on fixed seeds. The bounds are the project's targets (issue 3); the
// measured values are in the comments, so a regression shows as a lost margin.
#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace slt {
namespace {

const nlohmann::json kPaperProtocol = nlohmann::json::object();  // {} is the paper's protocol
const nlohmann::json kFaithful = {{"preset", "paper"}};
const nlohmann::json kDefault = nlohmann::json::object();

TEST(TrifocalLineEkfAccuracy, FaithfulSetting) {
  // Paper Fig. 4 reports below 0.01 m and 0.4 deg at +-2.5 px. The faithful setting (6-D
  // velocity state, one EKF update, (theta, lambda) residual, fixed R) meets the translation
  // figure but not reliably the rotation one on this protocol: measured 0.45 deg / 4.1 mm on
  // seeds 1-20 (0.40 / 0.60 deg on seeds 101-120 / 201-220); see docs/derivations.md. This guards
  // that level; the default setting below is the one that beats the paper.
  const TrialErrors e = FinalErrorOverTrials("trifocal_line_ekf", kFaithful, kPaperProtocol, 20);
  EXPECT_TRUE(e.all_finite);
  EXPECT_LT(e.mean.translation_m, 0.01);
  EXPECT_LT(e.mean.rotation_deg, 0.7);
}

TEST(TrifocalLineEkfAccuracy, DefaultSettingHalvesThePapersError) {
  // Measured 0.146 deg / 1.40 mm (worst trial 0.36 deg / 2.7 mm).
  const TrialErrors e = FinalErrorOverTrials("trifocal_line_ekf", kDefault, kPaperProtocol, 20);
  EXPECT_TRUE(e.all_finite);
  EXPECT_LE(e.mean.translation_m, 0.005);
  EXPECT_LE(e.mean.rotation_deg, 0.2);
}

TEST(TrifocalLineEkfAccuracy, NoiseFreeIsExact) {
  // Measured worst of 20 trials: 2e-5 deg / 1.9e-7 m.
  const TrialErrors e =
      FinalErrorOverTrials("trifocal_line_ekf", kDefault, {{"noise", {{"endpoint_px", 0.0}}}}, 20);
  EXPECT_LT(e.worst.translation_m, 1e-6);
  EXPECT_LT(e.worst.rotation_deg, 1e-4);
}

TEST(TrifocalLineEkfAccuracy, TwentyPercentOutlierSegments) {
  // Each observed segment, any image and frame, replaced by a random one with probability 0.2:
  // only 0.8^4 = 41 % of the lines have all four segments right. Measured 0.31 deg / 2.8 mm.
  const TrialErrors e =
      FinalErrorOverTrials("trifocal_line_ekf", kDefault, {{"outliers", {{"rate", 0.2}}}}, 20);
  EXPECT_TRUE(e.all_finite);
  EXPECT_LE(e.mean.translation_m, 0.01);
  EXPECT_LE(e.mean.rotation_deg, 0.5);
}

TEST(TrifocalLineEkfAccuracy, ThirtyPercentOutlierSegmentsWithThirtyLines) {
  // Beyond the bounds: only 0.7^4 = 24 % of the lines (about 7 of 30) have all four
  // segments right. A RANSAC start that accepted a two-line "consensus", and coasting at
  // constant velocity while lost, once sent single runs here metres away.
  const TrialErrors e = FinalErrorOverTrials("trifocal_line_ekf", kDefault,
                                             {{"max_features", 30}, {"outliers", {{"rate", 0.3}}}}, 20);
  EXPECT_TRUE(e.all_finite);
  // Measured 0.61 deg / 5.5 mm, worst trial 1.41 deg / 12 mm.
  EXPECT_LE(e.mean.translation_m, 0.01);
  EXPECT_LE(e.mean.rotation_deg, 1.0);
  EXPECT_LE(e.worst.translation_m, 0.03);
  EXPECT_LE(e.worst.rotation_deg, 3.0);
}

TEST(TrifocalLineEkfAccuracy, StaticCameraWithNoiseStaysNearItsStart) {
  // A camera at rest (the EuRoC excerpt's situation) with +-1 px noise: the error is the
  // estimate's noise, it does not grow.
  for (std::uint64_t seed : {1, 2, 3}) {
    SimulationConfig config =
        SimulationConfigFromJson({{"motion", {{"type", "static"}}}, {"noise", {{"endpoint_px", 1.0}}}}, "test");
    config.seed = seed;
    const SimulatedSequence sim = Simulate(config);
    auto tracker = CreateTracker("trifocal_line_ekf");
    const TrackRun run = RunTracker(*tracker, sim.sequence);
    for (size_t k = 0; k < run.outputs.size(); ++k) {
      const PoseError e = ErrorAt(sim, run, static_cast<int>(k));
      ASSERT_LT(e.translation_m, 2e-3) << "seed " << seed << " frame " << k;
      ASSERT_LT(e.rotation_deg, 0.25) << "seed " << seed << " frame " << k;
    }
  }
}

TEST(TrifocalLineEkfAccuracy, TwoLinesTrackAHundredFrames) {
  // Exactly two non-degenerate lines at +-0.5 px.
  double mean_translation = 0.0;
  const int trials = 20;
  for (int k = 0; k < trials; ++k) {
    SimulationConfig config = SimulationConfigFromJson({{"noise", {{"endpoint_px", 0.5}}}}, "test");
    config.seed = 1 + k;
    SimulatedSequence sim = Simulate(config);
    const std::vector<std::int64_t> ids = WellConditionedLines(sim, 2);
    ASSERT_EQ(ids.size(), 2u) << "seed " << config.seed;
    sim.sequence = KeepLines(sim.sequence, ids);
    auto tracker = CreateTracker("trifocal_line_ekf");
    const TrackRun run = RunTracker(*tracker, sim.sequence);
    for (size_t f = 0; f < run.outputs.size(); ++f) {
      ASSERT_TRUE(IsFinite(run.outputs[f].cam_from_world)) << "seed " << config.seed << " frame " << f;
      ASSERT_NE(run.outputs[f].status, TrackingStatus::kLost) << "seed " << config.seed << " frame " << f;
    }
    const PoseError e = ErrorAt(sim, run, 99);
    EXPECT_LE(e.translation_m, 0.03) << "seed " << config.seed;
    mean_translation += e.translation_m / trials;
  }
  EXPECT_LE(mean_translation, 0.02);
}

}  // namespace
}  // namespace slt
