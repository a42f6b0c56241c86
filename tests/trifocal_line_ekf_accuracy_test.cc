// Accuracy regressions of the trifocal-line EKF on the paper's protocol (Sec. 5.1): 40 random
// lines, 100 frames, per-frame motion up to 1.2 deg and 0.010 m, error of the pose at frame 100,
// mean over 20 trials on fixed seeds. Each test checks the project's target (issue 3) and, where
// the measured value is well inside it, a regression bound about 1.3x the measured value (1.5x
// where single trials can flip), so that a lost margin fails before the target does. The
// measured values are in the comments.
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
  // figure and is at the rotation one but not reliably below it on this protocol: 0.356 deg on
  // these seeds, 0.42 deg over seeds 1-200 (20-trial means 0.31-0.56 deg); see
  // docs/derivations.md Sec. 6. So 0.4 deg is not asserted here, where it would pass by the
  // choice of seeds; this guards the measured level. The default setting below is the one that
  // beats the paper.
  const TrialErrors e = FinalErrorOverTrials("trifocal_line_ekf", kFaithful, kPaperProtocol, 20);
  EXPECT_TRUE(e.all_finite);
  EXPECT_LT(e.mean.translation_m, 0.01);  // the paper's figure
  // Regression: measured 0.356 deg / 3.23 mm (worst trial 0.68 deg / 5.1 mm; before each
  // transfer was gated on its own, 0.448 deg / 4.06 mm).
  EXPECT_LT(e.mean.translation_m, 0.0042);
  EXPECT_LT(e.mean.rotation_deg, 0.46);
}

TEST(TrifocalLineEkfAccuracy, FaithfulSettingTracksPastTheReferenceRightCamera) {
  // Seed 2 passes within 2 cm of where the reference right camera stood: T over (I_1, I'_1, I_t)
  // degenerates for every line at once. With each transfer gated on its own, T' keeps measuring
  // and the reference stays (measured 0.095 deg / 1.5 mm at frame 100). Dropping whole lines
  // there forced a new reference at a poor pose, which the trajectory keeps: 1.17 deg.
  SimulationConfig config = SimulationConfigFromJson(kPaperProtocol, "test");
  config.seed = 2;
  const SimulatedSequence sim = Simulate(config);
  const Eigen::Vector3d reference_right_centre = sim.true_rig.right_from_left.Center();
  double closest_m = 1e9;
  for (const auto& stamped : sim.ground_truth) {
    closest_m = std::min(closest_m, (stamped.world_from_cam.translation - reference_right_centre).norm());
  }
  ASSERT_LT(closest_m, 0.02) << "the premise of the test: the trajectory passes the reference right camera";

  auto tracker = CreateTracker("trifocal_line_ekf", kFaithful);
  const TrackRun run = RunTracker(*tracker, sim.sequence);
  for (size_t f = 1; f < run.outputs.size(); ++f) {
    ASSERT_EQ(run.outputs[f].status, TrackingStatus::kTracking) << "frame " << f;
  }
  const PoseError e = ErrorAt(sim, run, 99);
  EXPECT_LT(e.rotation_deg, 0.3);
  EXPECT_LT(e.translation_m, 0.004);
}

TEST(TrifocalLineEkfAccuracy, DefaultSettingHalvesThePapersError) {
  const TrialErrors e = FinalErrorOverTrials("trifocal_line_ekf", kDefault, kPaperProtocol, 20);
  EXPECT_TRUE(e.all_finite);
  EXPECT_LE(e.mean.translation_m, 0.005);  // issue 3's target
  EXPECT_LE(e.mean.rotation_deg, 0.2);
  // Regression: measured 0.1465 deg / 1.40 mm (worst trial 0.36 deg / 2.7 mm).
  EXPECT_LE(e.mean.translation_m, 0.0019);
  EXPECT_LE(e.mean.rotation_deg, 0.19);
  EXPECT_LE(e.worst.translation_m, 0.0035);
  EXPECT_LE(e.worst.rotation_deg, 0.47);
}

TEST(TrifocalLineEkfAccuracy, NoiseFreeIsExact) {
  // Measured worst of 20 trials: 2e-5 deg / 1.9e-7 m.
  const TrialErrors e =
      FinalErrorOverTrials("trifocal_line_ekf", kDefault, {{"noise", {{"endpoint_px", 0.0}}}}, 20);
  EXPECT_TRUE(e.all_finite);
  EXPECT_LT(e.worst.translation_m, 1e-6);
  EXPECT_LT(e.worst.rotation_deg, 1e-4);
}

TEST(TrifocalLineEkfAccuracy, TwentyPercentOutlierSegments) {
  // Each observed segment, any image and frame, replaced by a random one with probability 0.2:
  // only 0.8^4 = 41 % of the lines have all four segments right.
  const TrialErrors e =
      FinalErrorOverTrials("trifocal_line_ekf", kDefault, {{"outliers", {{"rate", 0.2}}}}, 20);
  EXPECT_TRUE(e.all_finite);
  EXPECT_LE(e.mean.translation_m, 0.01);  // issue 3's target
  EXPECT_LE(e.mean.rotation_deg, 0.5);
  // Regression: measured 0.3125 deg / 2.79 mm (worst trial 1.13 deg / 8.8 mm).
  EXPECT_LE(e.mean.translation_m, 0.0037);
  EXPECT_LE(e.mean.rotation_deg, 0.41);
}

TEST(TrifocalLineEkfAccuracy, ThirtyPercentOutlierSegmentsWithThirtyLines) {
  // Beyond the bounds: only 0.7^4 = 24 % of the lines (about 7 of 30) have all four
  // segments right. A RANSAC start that accepted a two-line "consensus", and coasting at
  // constant velocity while lost, once sent single runs here metres away.
  const TrialErrors e = FinalErrorOverTrials("trifocal_line_ekf", kDefault,
                                             {{"max_features", 30}, {"outliers", {{"rate", 0.3}}}}, 20);
  EXPECT_TRUE(e.all_finite);
  // Measured 0.613 deg / 5.5 mm, worst trial 1.41 deg / 12 mm.
  EXPECT_LE(e.mean.translation_m, 0.0083);
  EXPECT_LE(e.mean.rotation_deg, 0.92);
  EXPECT_LE(e.worst.translation_m, 0.03);
  EXPECT_LE(e.worst.rotation_deg, 3.0);
}

TEST(TrifocalLineEkfAccuracy, StaticCameraWithNoiseStaysNearItsStart) {
  // A camera at rest (the EuRoC excerpt's situation) with +-1 px noise: the error is the
  // estimate's noise, it does not grow. Measured: at most 0.117 deg / 1.0 mm on any frame; mean
  // translation error 0.42 mm over frames 1-10 and 0.48 mm over frames 90-99.
  double early_m = 0.0, late_m = 0.0;
  for (std::uint64_t seed : {1, 2, 3}) {
    SimulationConfig config =
        SimulationConfigFromJson({{"motion", {{"type", "static"}}}, {"noise", {{"endpoint_px", 1.0}}}}, "test");
    config.seed = seed;
    const SimulatedSequence sim = Simulate(config);
    auto tracker = CreateTracker("trifocal_line_ekf");
    const TrackRun run = RunTracker(*tracker, sim.sequence);
    for (size_t k = 0; k < run.outputs.size(); ++k) {
      const PoseError e = ErrorAt(sim, run, static_cast<int>(k));
      ASSERT_LT(e.translation_m, 1.4e-3) << "seed " << seed << " frame " << k;
      ASSERT_LT(e.rotation_deg, 0.16) << "seed " << seed << " frame " << k;
      if (k >= 1 && k <= 10) early_m += e.translation_m;
      if (k >= 90 && k <= 99) late_m += e.translation_m;
    }
  }
  EXPECT_LE(late_m, 1.5 * early_m) << "the error grows at rest";
}

TEST(TrifocalLineEkfAccuracy, TwoLinesTrackAHundredFrames) {
  // Exactly two non-degenerate lines at +-0.5 px. Issue 3: finite poses, error <= 2 cm.
  // Measured: mean 0.96 deg / 8.4 mm, worst trial 2.98 deg / 22.7 mm; a tracker that never
  // moves is 35-110 mm off on these seeds.
  double mean_translation = 0.0, mean_rotation = 0.0;
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
    EXPECT_LE(e.rotation_deg, 4.0) << "seed " << config.seed;
    mean_translation += e.translation_m / trials;
    mean_rotation += e.rotation_deg / trials;
  }
  EXPECT_LE(mean_translation, 0.02);  // issue 3's target
  EXPECT_LE(mean_translation, 0.0125);  // regression
  EXPECT_LE(mean_rotation, 1.45);
}

}  // namespace
}  // namespace slt
