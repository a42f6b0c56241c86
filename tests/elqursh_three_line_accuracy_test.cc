// The Elqursh & Elgammal baseline (methods/elqursh_three_line) on simulated sequences: exact on
// noise-free scenes with primitive configurations, `lost` with the pose held where there is
// none (and predicted at constant velocity, decaying, where a motion was measured before), the
// motion of lost frames recovered, per-frame estimates that are never wild, and the
// paper's claim that the trifocal-line EKF beats it (Lee et al. 2015, Sec. 5.1, Fig. 6). Bounds
// are about 1.5x the measured values given in the comments (2-core VM).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/json_reader.h"
#include "geometry/se3.h"
#include "methods/elqursh_three_line/three_line_test_data.h"
#include "tests/test_support.h"

namespace slt {
namespace {

constexpr char kMethod[] = "elqursh_three_line";

// The paper protocol (40 random lines at about 0.5 m, +-2.5 px) with 30 % of the lines on
// cuboids: a rectangle and most of a box corner.
nlohmann::json WithCuboids(double noise_px, std::uint64_t seed = 1) {
  return {{"seed", seed}, {"scene", {{"paper", {{"cuboid_fraction", 0.3}}}}}, {"noise", {{"endpoint_px", noise_px}}}};
}

SimulatedSequence Simulated(const nlohmann::json& j) { return Simulate(SimulationConfigFromJson(j, "test")); }

TrackRun Track(const StereoSequence& sequence, const nlohmann::json& options = nlohmann::json::object()) {
  auto tracker = CreateTracker(kMethod, options);
  return RunTracker(*tracker, sequence);
}

// The error of the motion a tracked frame estimates since its reference, and the check that lost
// frames move by no more than the constant-velocity prediction allows (each lost frame's motion
// at most lost_velocity_decay = 0.5 times the previous frame's): what "never a wild pose" means
// for a tracker that chains increments. The reference is the previous tracked frame or one of
// the lost frames since (at its predicted pose); the error is the smallest over those frames.
struct StepErrors {
  double worst_rotation_deg = 0.0;
  double worst_translation_m = 0.0;
  int tracked = 0;
  int lost = 0;
  void Add(const StepErrors& other) {
    worst_rotation_deg = std::max(worst_rotation_deg, other.worst_rotation_deg);
    worst_translation_m = std::max(worst_translation_m, other.worst_translation_m);
    tracked += other.tracked;
    lost += other.lost;
  }
};
StepErrors CheckSteps(const SimulatedSequence& sim, const TrackRun& run) {
  StepErrors out;
  int last_tracked = 0;
  for (size_t k = 1; k < run.outputs.size(); ++k) {
    const TrackerOutput& o = run.outputs[k];
    EXPECT_TRUE(IsFinite(o.cam_from_world)) << "frame " << k;
    if (o.status == TrackingStatus::kLost) {
      ++out.lost;
      if (k >= 2 && run.outputs[k - 1].status == TrackingStatus::kLost) {
        const double step = LogSE3(o.cam_from_world * run.outputs[k - 1].cam_from_world.Inverse()).norm();
        const double previous =
            LogSE3(run.outputs[k - 1].cam_from_world * run.outputs[k - 2].cam_from_world.Inverse()).norm();
        EXPECT_LE(step, 0.5 * previous + 1e-12) << "frame " << k;
      }
      EXPECT_EQ(o.features_used, 0) << "frame " << k;
      continue;
    }
    ++out.tracked;
    double rotation_deg = INFINITY, translation_m = INFINITY;
    for (size_t j = last_tracked; j < k; ++j) {
      const Rigid3d estimated = o.cam_from_world * run.outputs[j].cam_from_world.Inverse();
      const Rigid3d truth = sim.ground_truth[k].world_from_cam.Inverse() * sim.ground_truth[j].world_from_cam;
      const Rigid3d error = estimated * truth.Inverse();
      rotation_deg = std::min(rotation_deg, RotationAngle(error.rotation) * 180.0 / M_PI);
      translation_m = std::min(translation_m, error.translation.norm());
    }
    out.worst_rotation_deg = std::max(out.worst_rotation_deg, rotation_deg);
    out.worst_translation_m = std::max(out.worst_translation_m, translation_m);
    last_tracked = static_cast<int>(k);
  }
  return out;
}

TEST(ElqurshThreeLine, NoiseFreeCuboidScenesAreExactOnEveryFrame) {
  for (std::uint64_t seed : {1, 2, 3}) {
    const SimulatedSequence sim = Simulated(WithCuboids(0.0, seed));
    const TrackRun run = Track(sim.sequence);
    for (size_t k = 1; k < run.outputs.size(); ++k) {
      ASSERT_EQ(run.outputs[k].status, TrackingStatus::kTracking) << "seed " << seed << " frame " << k;
      const PoseError e = ErrorAt(sim, run, static_cast<int>(k));
      ASSERT_LT(e.rotation_deg, 1e-8) << "seed " << seed << " frame " << k;
      ASSERT_LT(e.translation_m, 1e-10) << "seed " << seed << " frame " << k;
    }
  }
}

TEST(ElqurshThreeLine, ThreeLinesOfARectangleAreEnough) {
  // The registry's minimum: ids 0-2 are three edges of the first cuboid piece, a rectangle
  // (two parallel edges and the one joining them).
  const SimulatedSequence sim = Simulated(WithCuboids(0.0, 4));
  const StereoSequence three = KeepLines(sim.sequence, {0, 1, 2});
  ASSERT_EQ(FindTracker(kMethod).minimum_lines, 3);
  const TrackRun run = Track(three);
  for (size_t k = 1; k < run.outputs.size(); ++k) {
    ASSERT_EQ(run.outputs[k].status, TrackingStatus::kTracking) << "frame " << k;
    EXPECT_EQ(run.outputs[k].features_used, 3);
    EXPECT_LT(ErrorAt(sim, run, static_cast<int>(k)).rotation_deg, 1e-8) << "frame " << k;
  }
  // Two of them are not a configuration.
  const TrackRun two = Track(KeepLines(sim.sequence, {0, 1}));
  for (size_t k = 1; k < two.outputs.size(); ++k) ASSERT_EQ(two.outputs[k].status, TrackingStatus::kLost);
}

TEST(ElqurshThreeLine, WithoutAConfigurationEveryFrameIsLostAndThePoseHeld) {
  // Noise-free random lines of which no two are within 20 degrees of parallel: nothing to
  // start from, whatever the motion.
  const SimulatedSequence sim = Simulated({{"seed", 1}, {"noise", {{"endpoint_px", 0.0}}}});
  const std::vector<std::int64_t> ids = three_line_test::LinesWithoutAConfiguration(sim.lines);
  ASSERT_GE(ids.size(), 10u);
  const TrackRun run = Track(KeepLines(sim.sequence, ids));
  for (size_t k = 1; k < run.outputs.size(); ++k) {
    ASSERT_EQ(run.outputs[k].status, TrackingStatus::kLost) << "frame " << k;
    ASSERT_EQ(run.outputs[k].cam_from_world.ToMatrix4(), Eigen::Matrix4d::Identity()) << "frame " << k;
    EXPECT_GE(run.outputs[k].features_available, 10);
  }
}

TEST(ElqurshThreeLine, TheMotionOfLostFramesIsRecovered) {
  // Frames 40-44 see nothing: lost, the pose predicted from frame 39's motion with the velocity
  // halved on every lost frame; the reference stays frame 39, so frame 45 measures the whole
  // motion since and is exact again.
  SimulatedSequence sim = Simulated(WithCuboids(0.0, 5));
  for (int k = 40; k < 45; ++k) {
    sim.sequence.frames[k].left.clear();
    sim.sequence.frames[k].right.clear();
  }
  const TrackRun run = Track(sim.sequence);
  Vector6d velocity = LogSE3(run.outputs[39].cam_from_world * run.outputs[38].cam_from_world.Inverse());
  for (int k = 40; k < 45; ++k) {
    EXPECT_EQ(run.outputs[k].status, TrackingStatus::kLost) << "frame " << k;
    velocity *= 0.5;
    const Rigid3d predicted = ExpSE3(velocity) * run.outputs[k - 1].cam_from_world;
    EXPECT_TRUE(run.outputs[k].cam_from_world.ToMatrix4().isApprox(predicted.ToMatrix4(), 1e-12)) << "frame " << k;
  }
  EXPECT_GT(ErrorAt(sim, run, 44).rotation_deg, 0.5);  // the prediction falls behind
  for (int k = 45; k < static_cast<int>(run.outputs.size()); ++k) {
    ASSERT_EQ(run.outputs[k].status, TrackingStatus::kTracking) << "frame " << k;
    ASSERT_LT(ErrorAt(sim, run, k).rotation_deg, 1e-8) << "frame " << k;
  }
}

TEST(ElqurshThreeLine, RandomLinesGiveLostFramesNotWildPoses) {
  // The paper protocol without cuboids, +-2.5 px, seeds 1-10: no configuration in most frames
  // (measured: 498 of 990 frames lost; 620 when a reference without a configuration was held for
  // max_lost_frames). Where two lines happen to lie within the tolerance of parallel and a third
  // of orthogonal, the consensus and its refinement give a pose: measured worst increment error
  // 2.1 deg / 19 mm (1.5 deg / 16 mm with the reference held).
  StepErrors all;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const SimulatedSequence sim = Simulated({{"seed", seed}});
    all.Add(CheckSteps(sim, Track(sim.sequence)));
  }
  EXPECT_GT(all.lost, 450);
  EXPECT_LT(all.worst_rotation_deg, 2.3);
  EXPECT_LT(all.worst_translation_m, 0.024);
}

TEST(ElqurshThreeLine, CuboidScenesWithNoiseAndThePapersClaim) {
  // +-2.5 px, 30 % of the lines on cuboids, seeds 1-10: measured 9 of 990 frames lost, worst
  // increment error 1.7 deg / 15 mm (median 0.18 deg); at frame 100 a mean error of
  // 2.2 deg / 21 mm. The paper's claim (Sec. 5.1, Fig. 6) on the scenes where Elqursh's method
  // has what it needs: the trifocal-line EKF measured 0.14 deg / 1.2 mm on the same seeds.
  StepErrors all;
  PoseError final_mean;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const SimulatedSequence sim = Simulated(WithCuboids(2.5, seed));
    const TrackRun run = Track(sim.sequence);
    all.Add(CheckSteps(sim, run));
    const PoseError e = ErrorAt(sim, run, static_cast<int>(run.outputs.size()) - 1);
    final_mean.rotation_deg += e.rotation_deg / 10;
    final_mean.translation_m += e.translation_m / 10;
  }
  EXPECT_LT(all.lost, 20);
  EXPECT_LT(all.worst_rotation_deg, 2.5);
  EXPECT_LT(all.worst_translation_m, 0.022);
  EXPECT_LT(final_mean.rotation_deg, 3.3);
  EXPECT_LT(final_mean.translation_m, 0.032);
  const TrialErrors ekf = FinalErrorOverTrials("trifocal_line_ekf", nlohmann::json::object(), WithCuboids(2.5), 10);
  EXPECT_LT(3.0 * ekf.mean.rotation_deg, final_mean.rotation_deg);
  EXPECT_LT(3.0 * ekf.mean.translation_m, final_mean.translation_m);
}

TEST(ElqurshThreeLine, BadOptionsNameTheKey) {
  try {
    CreateTracker(kMethod, {{"min_inliers", 2}}, "t.json");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("t.json: key 'min_inliers'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace slt
