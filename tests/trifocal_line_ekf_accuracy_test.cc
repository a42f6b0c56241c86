// Accuracy regressions of the trifocal-line EKF on the paper's protocol (Sec. 5.1): 40 random
// lines, 100 frames, per-frame motion up to 1.2 deg and 0.010 m, error of the pose at frame 100,
// mean over 20 trials on fixed seeds (100 for the faithful setting, see there). Each test checks the project's target (issue 3) and, where
// the measured value is well inside it, a regression bound about 1.3x the measured value (1.5x
// where single trials can flip), so that a lost margin fails before the target does. The
// measured values are in the comments.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "common/json_reader.h"
#include "common/random.h"
#include "evaluation/metrics.h"
#include "methods/trifocal_line_ekf/line_transfer_model.h"
#include "tests/test_support.h"

namespace slt {
namespace {

const nlohmann::json kPaperProtocol = nlohmann::json::object();  // {} is the paper's protocol
const nlohmann::json kFaithful = {{"preset", "paper"}};
const nlohmann::json kDefault = nlohmann::json::object();

// 1.4826 x the median absolute value: the standard deviation of the Gaussian bulk of `values`,
// not inflated by the heavy tail that near-degenerate transfers give.
double RobustSpread(std::vector<double> values) {
  for (double& v : values) v = std::abs(v);
  return 1.4826 * ComputeStatistics(std::move(values)).median;
}

TEST(TrifocalLineEkfAccuracy, FaithfulFixedRIsTheResidualSpreadAtTheTruePose) {
  // The paper leaves R's values unstated; the preset takes the spread of each (theta, lambda)
  // residual at the true pose under the paper protocol's noise. Re-measured here on 40 other
  // seeds than the 40 it was chosen on (sets of 10 seeds vary by about 5 %): a change of the residual, the transfer or the simulator's
  // noise that leaves the preset's R mis-scaled fails this test (the earlier 0.005 rad was
  // 2.4x too small).
  auto tracker = CreateTracker("trifocal_line_ekf", kFaithful);
  LineTransferOptions options;
  JsonReader reader(tracker->Options().at("measurement"), "test", "measurement");
  ReadLineTransferOptions(reader, &options);
  ASSERT_EQ(options.residual, LineResidual::kThetaLambda);
  ASSERT_EQ(options.noise, MeasurementNoise::kFixed);
  LineTransferModel model(options);

  std::vector<double> residuals[4];
  for (std::uint64_t seed = 101; seed <= 140; ++seed) {
    SimulationConfig config = SimulationConfigFromJson(kPaperProtocol, "test");
    config.seed = seed;
    const SimulatedSequence sim = Simulate(config);
    model.Reset(sim.sequence.rig);
    model.SetReference(sim.sequence.frames[0]);
    for (size_t f = 1; f < sim.sequence.frames.size(); ++f) {
      model.SetCurrent(sim.sequence.frames[f]);
      const Rigid3d cam_from_ref = sim.ground_truth[f].world_from_cam.Inverse();  // world = reference
      for (int i = 0; i < model.NumFeatures(); ++i) {
        FeatureBlock block;
        if (!model.Evaluate(i, cam_from_ref, false, &block) || block.measured_rows != FeatureBlock::kAllRows) continue;
        for (int row = 0; row < 4; ++row) residuals[row].push_back(block.residual(row));
      }
    }
  }
  ASSERT_GT(residuals[0].size(), 10000u);
  // Measured on these seeds: 0.0118, 1.92, 0.0118, 1.90 (rad, px, rad, px); on seeds 1-40, where
  // the preset's values come from, 0.0117, 1.86, 0.0117, 1.91.
  const double fixed_sigma[4] = {options.fixed_sigma_rad, options.fixed_sigma_px, options.fixed_sigma_rad,
                                 options.fixed_sigma_px};
  for (int row = 0; row < 4; ++row) {
    EXPECT_NEAR(RobustSpread(residuals[row]) / fixed_sigma[row], 1.0, 0.1) << "residual row " << row;
  }
}

TEST(TrifocalLineEkfAccuracy, FaithfulSetting) {
  // Paper Fig. 4 reports below 0.01 m and 0.4 deg at +-2.5 px, each a mean over 20 trials. The
  // faithful setting (6-D velocity state, one EKF update, (theta, lambda) residual, fixed R)
  // is at about 0.36 deg: 0.364 deg over 1 200 trials (results/faithful_fixed_r), and 51 of
  // those 60 sets of 20 trials below 0.4 deg. A single set of 20 would pass or fail by the
  // choice of seeds (seeds 1-20: 0.404 deg), so the target is checked on the mean over 100
  // seeds, whose spread is less than half a 20-trial mean's (1/sqrt(5)).
  const TrialErrors e = FinalErrorOverTrials("trifocal_line_ekf", kFaithful, kPaperProtocol, 100);
  EXPECT_TRUE(e.all_finite);
  // Measured 0.331 deg / 2.96 mm (worst trial 0.93 deg). The earlier guessed R (0.005 rad, 2 px)
  // gives 0.369 deg / 3.50 mm on these seeds and passes too: what guards R is the test above.
  EXPECT_LT(e.mean.rotation_deg, 0.4);        // the paper's figure
  EXPECT_LT(e.mean.translation_m, 0.0039);  // regression (the paper's figure is 0.01 m)
}

TEST(TrifocalLineEkfAccuracy, FaithfulSettingTracksPastTheReferenceRightCamera) {
  // Seed 2 passes within 2 cm of where the reference right camera stood: T over (I_1, I'_1, I_t)
  // degenerates for every line at once. With each transfer gated on its own, T' keeps measuring
  // and the reference stays. Dropping whole lines there forced a new reference at a poor pose,
  // which the rest of the trajectory keeps.
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
  PoseError mean;
  for (size_t f = 1; f < run.outputs.size(); ++f) {
    ASSERT_EQ(run.outputs[f].status, TrackingStatus::kTracking) << "frame " << f;
    const PoseError e = ErrorAt(sim, run, static_cast<int>(f));
    mean.rotation_deg += e.rotation_deg / (run.outputs.size() - 1);
    mean.translation_m += e.translation_m / (run.outputs.size() - 1);
  }
  // The whole trajectory, not one frame: the error along this run swings between 0.1 and 3.7 deg
  // (peak at frames 40-44). Measured mean over frames 0.85 deg / 7.6 mm; with the earlier guessed
  // R 1.30 deg / 11.1 mm. This test used to bound frame 100 alone (< 0.3 deg, 4 mm), which the
  // guessed R happened to meet (0.095 deg) and the measured R does not (0.71 deg / 5.3 mm).
  EXPECT_LT(mean.rotation_deg, 1.1);
  EXPECT_LT(mean.translation_m, 0.0099);
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
  EXPECT_LE(mean_translation, 0.0125);  // regression (issue 3's target was 0.02 m)
  EXPECT_LE(mean_rotation, 1.45);
}

TEST(TrifocalLineEkfAccuracy, RobustStartKeepsWhatItsSampleLeavesUndetermined) {
  // Issue 16: the corridor walk at +-0.25 px with the preset long_run_consistent and R at that
  // noise (long_corridor_placement_low_noise), first 20 frames of its trials 0-3. On trial 3 the
  // robust start's best hypothesis at frame 2 came from vertical lines, which leave the height to
  // their noise: it sat 0.35 m off in height, and the filter, re-seeded there, ends metres off
  // (docs/long_sequences.md). With filter.robust_max_sigma (the preset's 0.05) a hypothesis keeps
  // the start's value along such directions. Measured with it: at most 4.9 mm on any frame,
  // 0.28-0.59 mm at frame 19; without it, trial 3 is 3.7 m off at frame 19.
  const nlohmann::json simulation = {
      {"frames", 20},
      {"scene", {{"type", "corridor"}}},
      {"motion",
       {{"type", "forward"},
        {"forward", {{"step_m", 0.02}, {"wobble_m", 0.03}, {"wobble_deg", 3.0}, {"wobble_period_frames", 35}}}}},
      {"observation", {{"clip_to_image", true}}},
      {"noise", {{"endpoint_px", 0.25}, {"endpoints", "fixed"}}}};
  nlohmann::json options = {{"preset", "long_run_consistent"},
                             {"measurement", {{"endpoint_sigma_px", 0.25 / std::sqrt(3.0)}}}};
  for (int trial = 0; trial < 4; ++trial) {
    SimulationConfig config = SimulationConfigFromJson(simulation, "test");
    config.seed = TrialSeed(1, trial);
    const SimulatedSequence sim = Simulate(config);
    auto tracker = CreateTracker("trifocal_line_ekf", options);
    const TrackRun run = RunTracker(*tracker, sim.sequence);
    double largest_m = 0.0;
    for (int k = 0; k < 20; ++k) largest_m = std::max(largest_m, ErrorAt(sim, run, k).translation_m);
    EXPECT_LT(largest_m, 0.008) << "trial " << trial;
    EXPECT_LT(ErrorAt(sim, run, 19).translation_m, 0.0015) << "trial " << trial;
    if (trial != 3) continue;
    // The failure guarded against, still there without the option.
    options["filter"]["robust_max_sigma"] = 0.0;
    tracker = CreateTracker("trifocal_line_ekf", options);
    EXPECT_GT(ErrorAt(sim, RunTracker(*tracker, sim.sequence), 19).translation_m, 0.1);
  }
}

}  // namespace
}  // namespace slt
