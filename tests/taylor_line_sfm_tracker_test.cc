// The Taylor & Kriegman baseline as a tracker on simulated sequences: what the shared suite does
// not check (two lines suffice, the window's length, the lost status with one line, the
// solver's iteration count).
#include <gtest/gtest.h>

#include "methods/taylor_line_sfm/taylor_line_sfm.h"
#include "tests/test_support.h"

namespace slt {
namespace {

SimulatedSequence Simulated(const nlohmann::json& j) { return Simulate(SimulationConfigFromJson(j, "test simulation")); }

TEST(TaylorLineSfm, TwoLinesSeenInStereoAreEnough) {
  // Two stereo lines over two frames over-determine the motion (metric scale from the rig):
  // noise-free, the pose is exact on every frame.
  const SimulatedSequence sim = Simulated({{"frames", 40}, {"noise", {{"endpoint_px", 0.0}}}});
  SimulatedSequence two = sim;
  two.sequence = KeepLines(sim.sequence, WellConditionedLines(sim, 2));
  TaylorLineSfmTracker tracker{TaylorLineSfmOptions()};
  const TrackRun run = RunTracker(tracker, two.sequence);
  for (size_t k = 1; k < run.outputs.size(); ++k) {
    ASSERT_EQ(run.outputs[k].status, TrackingStatus::kTracking) << "frame " << k;
    EXPECT_EQ(run.outputs[k].features_used, 2) << "frame " << k;
    const PoseError e = ErrorAt(two, run, static_cast<int>(k));
    EXPECT_LT(e.translation_m, 1e-6) << "frame " << k;
    EXPECT_LT(e.rotation_deg, 1e-4) << "frame " << k;
  }
}

TEST(TaylorLineSfm, OneLineIsLost) {
  const SimulatedSequence sim = Simulated({{"frames", 10}, {"noise", {{"endpoint_px", 1.0}}}});
  TaylorLineSfmTracker tracker{TaylorLineSfmOptions()};
  const TrackRun run = RunTracker(tracker, KeepLines(sim.sequence, WellConditionedLines(sim, 1)));
  for (size_t k = 1; k < run.outputs.size(); ++k) {
    EXPECT_EQ(run.outputs[k].status, TrackingStatus::kLost) << "frame " << k;
    EXPECT_EQ(run.outputs[k].features_used, 0) << "frame " << k;
    EXPECT_TRUE(IsFinite(run.outputs[k].cam_from_world)) << "frame " << k;
  }
  EXPECT_EQ(tracker.counters().lost_frames, 9);
  EXPECT_EQ(tracker.counters().solved_frames, 0);
}

TEST(TaylorLineSfm, TheWindowHoldsTheLastKFramesOrAllOfThem) {
  const SimulatedSequence sim = Simulated({{"frames", 12}, {"noise", {{"endpoint_px", 1.0}}}});
  for (int k : {0, 3, 5}) {
    TaylorLineSfmOptions options;
    options.window_frames = k;
    TaylorLineSfmTracker tracker(options);
    RunTracker(tracker, sim.sequence);
    EXPECT_EQ(tracker.window().NumFrames(), k == 0 ? 12 : k) << "K = " << k;
    EXPECT_EQ(tracker.last_solve().frames, k == 0 ? 12 : k) << "K = " << k;
  }
}

TEST(TaylorLineSfm, CountsTheSolversIterations) {
  const SimulatedSequence sim = Simulated({{"frames", 20}});
  TaylorLineSfmOptions options;
  options.max_iterations = 3;
  TaylorLineSfmTracker tracker(options);
  RunTracker(tracker, sim.sequence);
  const TaylorLineSfmTracker::Counters& c = tracker.counters();
  EXPECT_EQ(c.solved_frames, 19);
  EXPECT_EQ(c.solves, 19);  // no outliers: one Ceres run per frame
  EXPECT_EQ(c.rejected_observations, 0);
  EXPECT_EQ(c.solve_failures, 0);
  EXPECT_GE(c.iterations, c.solves);      // at least one step per run
  EXPECT_LE(c.iterations, 3 * c.solves);  // at most max_iterations
  EXPECT_GT(c.lines_triangulated, 20);
}

}  // namespace
}  // namespace slt
