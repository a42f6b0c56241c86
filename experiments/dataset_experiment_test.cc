// run_experiment with recorded sequences as the source (ExperimentConfig::datasets): a run on a
// short rendered sequence written in EuRoC's layout (the config: experiment_config_test.cc).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "experiments/experiment_config.h"
#include "experiments/experiment_runner.h"
#include "render/sequence_renderer.h"

namespace slt {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

TEST(DatasetExperiment, RunsEveryMethodOnARenderedSequenceWithItsGroundTruth) {
  // 8 frames of the rendered room (320 x 240), written as EuRoC writes its sequences.
  const json rig = {{"width", 320},
                    {"height", 240},
                    {"left", {{"fx", 250.0}, {"fy", 250.0}, {"cx", 159.5}, {"cy", 119.5}}},
                    {"right", {{"fx", 250.0}, {"fy", 250.0}, {"cx", 159.5}, {"cy", 119.5}}},
                    {"right_from_left", {{"R", {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}, {"t", {-0.1, 0, 0}}}}};
  const SimulationConfig sim = SimulationConfigFromJson({{"scene", {{"type", "room"}}}, {"frames", 8}, {"rig", rig}}, "sim");
  const SimulatedSequence sequence = Simulate(sim);
  const fs::path dir = fs::path(::testing::TempDir()) / ("dataset_experiment_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  WriteEurocSequence(dir.string(), sequence, sim, 1);

  const ExperimentConfig config = ExperimentConfigFromJson(
      {{"name", "rendered"},
       {"trials", 1},
       {"datasets", {{{"path", dir.string()}, {"label", "room"}}}},
       {"methods", {"trifocal_line_ekf", "constant_pose"}},
       {"save_trajectories", 1}},
      "cfg.json");
  RunOptions options;
  options.threads = 1;
  const ExperimentRun run = RunExperiment(config, options);
  ASSERT_EQ(run.trials.size(), 2u);
  double path = 0.0;
  for (int k = 1; k < 8; ++k) {
    path += (sequence.ground_truth[k].world_from_cam.translation - sequence.ground_truth[k - 1].world_from_cam.translation).norm();
  }
  for (const TrialResult& r : run.trials) {
    EXPECT_EQ(r.frames, 8);
    EXPECT_TRUE(r.finite);
    EXPECT_NEAR(r.metrics[kPathLengthM], path, 1e-6);
    ASSERT_EQ(r.ground_truth.size(), 8u);
    EXPECT_TRUE(r.ground_truth[0].world_from_cam.translation.isZero(1e-9));
  }
  // The constant pose's error is the ground truth's own motion; the line tracker follows it.
  const TrialResult& ekf = run.trials[0];
  const TrialResult& still = run.trials[1];
  EXPECT_NEAR(still.metrics[kFinalTransErrM], sequence.ground_truth[7].world_from_cam.translation.norm() -
                                                    sequence.ground_truth[0].world_from_cam.translation.norm() * 0.0,
              0.05);
  EXPECT_LT(ekf.metrics[kAteTransM], 0.5 * still.metrics[kAteTransM]);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace slt
