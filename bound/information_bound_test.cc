#include "bound/information_bound.h"

#include <gtest/gtest.h>

#include "common/random.h"
#include "simulator/simulation_config.h"

namespace slt {
namespace {

// The start of long_room's first trial (the room loop), at the given endpoint noise.
SimulatedSequence RoomLoop(int frames, double noise_px) {
  return Simulate(SimulationConfigFromJson(
      {{"frames", frames},
       {"seed", TrialSeed(1, 0)},
       {"scene", {{"type", "room"}}},
       {"motion", {{"type", "loop"}, {"loop", {{"radius_x_m", 0.2}, {"radius_z_m", 0.28}}}}},
       {"observation", {{"clip_to_image", true}}},
       {"noise", {{"endpoint_px", noise_px}}}},
      "test"));
}

double LargestError(const SimulatedSequence& sim, const std::vector<int>& frames, const std::vector<Rigid3d>& cam_from_world) {
  double largest = 0.0;
  for (size_t n = 0; n < frames.size(); ++n) {
    largest = std::max(largest, (cam_from_world[n].Center() - sim.ground_truth[frames[n]].world_from_cam.translation).norm());
  }
  return largest;
}

TEST(InformationBound, RecoversTheTruthFromNoiseFreeObservations) {
  const SimulatedSequence sim = RoomLoop(41, 0.0);
  InformationBoundOptions options;
  const InformationBound bound = ComputeInformationBound(sim, options);
  ASSERT_EQ(bound.frames, (std::vector<int>{0, 10, 20, 30, 40}));
  ASSERT_EQ(bound.causal_cam_from_world.size(), 5u);
  ASSERT_EQ(bound.smoother_cam_from_world.size(), 5u);
  EXPECT_EQ(bound.unsolved, 0);
  EXPECT_LT(LargestError(sim, bound.frames, bound.causal_cam_from_world), 1e-9);
  EXPECT_LT(LargestError(sim, bound.frames, bound.smoother_cam_from_world), 1e-9);
}

TEST(InformationBound, CausalAtTheLastFrameIsTheSmootherThere) {
  // The causal solve at the last keyframe sees every frame, as the smoother does: the same
  // minimum, reached from the previous causal solve (warm) or from the truth.
  const SimulatedSequence sim = RoomLoop(41, 1.0);
  const InformationBound bound = ComputeInformationBound(sim, InformationBoundOptions());
  EXPECT_EQ(bound.unsolved, 0);
  const Eigen::Vector3d causal = bound.causal_cam_from_world.back().Center();
  const Eigen::Vector3d smoother = bound.smoother_cam_from_world.back().Center();
  EXPECT_LT((causal - smoother).norm(), 1e-6);
  // The noise moves the estimate, by a centimetre or two over the first 4 cm of the loop (the
  // first frames' vertical is weakly determined).
  const double largest = LargestError(sim, bound.frames, bound.smoother_cam_from_world);
  EXPECT_GT(largest, 1e-5);
  EXPECT_LT(largest, 0.03);
}

TEST(InformationBound, RestrictionsKeepTheGaugeAndTheTruth) {
  // A window without the first frame holds its own first frame (the gauge); the restrictions
  // leave noise-free observations exact.
  const SimulatedSequence sim = RoomLoop(41, 0.0);
  InformationBoundOptions options;
  options.window_frames = 15;
  options.structure_interval = 5;
  options.taylor_residual = true;
  options.min_epipolar_angle_deg = 3.0;
  options.smoother = false;
  const InformationBound bound = ComputeInformationBound(sim, options);
  EXPECT_EQ(bound.unsolved, 0);
  EXPECT_LT(LargestError(sim, bound.frames, bound.causal_cam_from_world), 1e-9);
  // With noise, every windowed solve still holds its gauge and places its frame near the truth.
  const SimulatedSequence noisy = RoomLoop(41, 1.0);
  InformationBoundOptions window;
  window.window_frames = 15;
  window.smoother = false;
  const InformationBound noisy_bound = ComputeInformationBound(noisy, window);
  EXPECT_EQ(noisy_bound.unsolved, 0);
  EXPECT_LT(LargestError(noisy, noisy_bound.frames, noisy_bound.causal_cam_from_world), 0.05);
}

}  // namespace
}  // namespace slt
