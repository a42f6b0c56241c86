// The tracker's lost-state policy (elqursh_three_line.h, step 4): a reference whose lines hold no
// candidate configuration is replaced at once, and a lost frame's pose is the constant-velocity
// prediction. The accuracy on simulated sequences is tested in
// tests/elqursh_three_line_accuracy_test.cc.
#include "methods/elqursh_three_line/elqursh_three_line.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "common/json_reader.h"
#include "geometry/se3.h"
#include "methods/elqursh_three_line/three_line_test_data.h"
#include "simulator/simulation_config.h"
#include "simulator/simulator.h"

namespace slt {
namespace {

constexpr int kDrop = 30;           // the frame that sees only lines without a configuration
constexpr std::int64_t kNewId = 1000;  // ids of the lines found again after it

// The paper protocol, noise-free, with 30 % of the lines on cuboids.
SimulatedSequence CuboidScene() {
  return Simulate(SimulationConfigFromJson(
      {{"seed", 5}, {"scene", {{"paper", {{"cuboid_fraction", 0.3}}}}}, {"noise", {{"endpoint_px", 0.0}}}}, "test"));
}

// What an image front end does when a frame's detections miss most lines (KITTI,
// docs/baselines.md):
// frame kDrop keeps only `kept`; the other lines are found again from frame kDrop + 1 on, as new
// tracks (new ids), so that no later frame matches them with a reference before kDrop + 1.
StereoSequence DropConfigurationsForOneFrame(const StereoSequence& sequence, const std::vector<std::int64_t>& kept) {
  StereoSequence out = sequence;
  const auto is_kept = [&](std::int64_t id) { return std::find(kept.begin(), kept.end(), id) != kept.end(); };
  for (size_t k = kDrop; k < out.frames.size(); ++k) {
    for (std::vector<LineObservation>* side : {&out.frames[k].left, &out.frames[k].right}) {
      if (static_cast<int>(k) == kDrop) {
        const auto dropped = [&](const LineObservation& o) { return !is_kept(o.id); };
        side->erase(std::remove_if(side->begin(), side->end(), dropped), side->end());
      } else {
        for (LineObservation& o : *side) o.id += is_kept(o.id) ? 0 : kNewId;
      }
    }
  }
  return out;
}

std::vector<TrackerOutput> TrackAll(const StereoSequence& sequence, const nlohmann::json& options = nlohmann::json::object()) {
  std::unique_ptr<PoseTracker> tracker = ElqurshThreeLineInfo().create(options, "test");
  // (TrackSequence lives in the registry, which links this library.)
  tracker->Reset(sequence.rig);
  std::vector<TrackerOutput> outputs;
  for (const StereoFrame& frame : sequence.frames) outputs.push_back(tracker->Track(frame));
  return outputs;
}

// The motion of frame k since frame j, estimated against the truth: the error's angle (deg) and
// its translation (m).
std::pair<double, double> StepError(const SimulatedSequence& sim, const std::vector<TrackerOutput>& out, int j, int k) {
  const Rigid3d estimated = out[k].cam_from_world * out[j].cam_from_world.Inverse();
  const Rigid3d truth = sim.ground_truth[k].world_from_cam.Inverse() * sim.ground_truth[j].world_from_cam;
  const Rigid3d error = estimated * truth.Inverse();
  return {RotationAngle(error.rotation) * 180.0 / M_PI, error.translation.norm()};
}

TEST(ElqurshThreeLineTracker, AReferenceWithoutAConfigurationIsReplacedAtOnce) {
  const SimulatedSequence sim = CuboidScene();
  const std::vector<std::int64_t> kept = three_line_test::LinesWithoutAConfiguration(sim.lines);
  ASSERT_GE(kept.size(), 10u);
  const std::vector<TrackerOutput> out = TrackAll(DropConfigurationsForOneFrame(sim.sequence, kept));
  ASSERT_EQ(out.size(), sim.sequence.frames.size());
  for (int k = 1; k < kDrop; ++k) ASSERT_EQ(out[k].status, TrackingStatus::kTracking) << "frame " << k;
  // kDrop has no configuration with kDrop - 1, kDrop + 1 none with kDrop (its found-again lines
  // are new): both lost, each becoming the reference. Holding the reference instead loses every
  // frame until max_lost_frames (10) have failed, since no later frame matches more of its lines.
  for (int k : {kDrop, kDrop + 1}) {
    EXPECT_EQ(out[k].status, TrackingStatus::kLost) << "frame " << k;
    EXPECT_EQ(out[k].reason, StatusReason::kUnconstrained) << "frame " << k;
    EXPECT_EQ(out[k].features_used, 0) << "frame " << k;
  }
  for (int k = kDrop + 2; k < static_cast<int>(out.size()); ++k) {
    ASSERT_EQ(out[k].status, TrackingStatus::kTracking) << "frame " << k;
    const auto [rotation_deg, translation_m] = StepError(sim, out, k - 1, k);
    ASSERT_LT(rotation_deg, 1e-8) << "frame " << k;
    ASSERT_LT(translation_m, 1e-10) << "frame " << k;
  }
}

TEST(ElqurshThreeLineTracker, ALostFramesPoseIsTheConstantVelocityPrediction) {
  const SimulatedSequence sim = CuboidScene();
  const StereoSequence sequence =
      DropConfigurationsForOneFrame(sim.sequence, three_line_test::LinesWithoutAConfiguration(sim.lines));
  for (double decay : {0.0, 0.5, 1.0}) {
    const std::vector<TrackerOutput> out = TrackAll(sequence, {{"lost_velocity_decay", decay}});
    // The velocity: the motion measured last (frame kDrop - 1 against kDrop - 2), times the
    // decay on every lost frame.
    Vector6d velocity = LogSE3(out[kDrop - 1].cam_from_world * out[kDrop - 2].cam_from_world.Inverse());
    for (int k : {kDrop, kDrop + 1}) {
      ASSERT_EQ(out[k].status, TrackingStatus::kLost) << "decay " << decay << " frame " << k;
      velocity *= decay;
      const Rigid3d predicted = ExpSE3(velocity) * out[k - 1].cam_from_world;
      EXPECT_TRUE(out[k].cam_from_world.ToMatrix4().isApprox(predicted.ToMatrix4(), 1e-12)) << "decay " << decay;
    }
    // Coasting at the last velocity is closer to the truth than holding the pose: the
    // simulated motion changes slowly from frame to frame.
    if (decay == 1.0) {
      const auto coasted = StepError(sim, out, kDrop - 1, kDrop);
      const auto held = StepError(sim, TrackAll(sequence, {{"lost_velocity_decay", 0.0}}), kDrop - 1, kDrop);
      EXPECT_LT(coasted.second, 0.5 * held.second);
    }
  }
}

TEST(ElqurshThreeLineTracker, BadDecayNamesTheKey) {
  try {
    ElqurshThreeLineInfo().create({{"lost_velocity_decay", 1.5}}, "t.json");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("t.json: key 'lost_velocity_decay'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace slt
