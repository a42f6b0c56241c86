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
  // The first 10 frames of the rendered 200-frame room loop (about 1 cm and 0.3 deg per frame,
  // the default 640 x 480 rig), written as EuRoC writes its sequences.
  const SimulationConfig sim = SimulationConfigFromJson({{"scene", {{"type", "room"}}}, {"frames", 200}}, "sim");
  SimulatedSequence sequence = Simulate(sim);
  const int frames = 10;
  sequence.ground_truth.resize(frames);
  sequence.sequence.frames.resize(frames);
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
  for (int k = 1; k < frames; ++k) {
    path += (sequence.ground_truth[k].world_from_cam.translation - sequence.ground_truth[k - 1].world_from_cam.translation).norm();
  }
  for (const TrialResult& r : run.trials) {
    EXPECT_EQ(r.frames, frames);
    EXPECT_TRUE(r.finite);
    EXPECT_NEAR(r.metrics[kPathLengthM], path, 1e-6);
    ASSERT_EQ(r.ground_truth.size(), static_cast<size_t>(frames));
    EXPECT_TRUE(r.ground_truth[0].world_from_cam.translation.isZero(1e-9));
  }
  // The constant pose's error is the ground truth's own motion; the line tracker follows it.
  const TrialResult& ekf = run.trials[0];
  const TrialResult& still = run.trials[1];
  EXPECT_NEAR(still.metrics[kFinalTransErrM],
              (sequence.ground_truth[frames - 1].world_from_cam.translation -
               sequence.ground_truth[0].world_from_cam.translation).norm(),
              1e-6);
  EXPECT_LT(ekf.metrics[kAteTransM], 0.5 * still.metrics[kAteTransM]);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace slt
