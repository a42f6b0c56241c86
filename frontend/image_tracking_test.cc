#include "frontend/image_tracking.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "common/json_reader.h"
#include "frontend/image_sequence.h"

namespace slt {
namespace {

// The real excerpts (../shared/data, README there), or the folder named by SLT_SHARED_DATA.
std::string SharedData() {
  const char* env = std::getenv("SLT_SHARED_DATA");
  return env != nullptr ? env : SLT_SHARED_DATA_DIR;
}

// The options `method` runs with on the KITTI excerpt: its entry in the excerpt's
// tracker_options of experiments/configs/datasets.json (the car's motion prior; docs/datasets.md),
// the one place KITTI runs take them from.
nlohmann::json KittiTrackerOptions(const std::string& method) {
  const std::string config = std::string(SLT_SOURCE_DIR) + "/experiments/configs/datasets.json";
  const nlohmann::json datasets = ReadJsonFile(config).at("datasets");
  for (const nlohmann::json& dataset : datasets) {
    if (dataset.at("path").get<std::string>().find("kitti_excerpt_1") == std::string::npos) continue;
    return dataset.value("tracker_options", nlohmann::json::object()).value(method, nlohmann::json::object());
  }
  ADD_FAILURE() << config << " lists no kitti_excerpt_1";
  return nlohmann::json::object();
}

TEST(ImageTracker, KittiPredictionReachesTheFrontEndAndSeedsMostLines) {
  // The first frames of the KITTI excerpt (about 1.2 m per frame), the tracker with the
  // options KITTI runs use: after the tracker's first update the front end gets the tracker's
  // predicted motion and seeds most tracked lines with it; once the filter's start is over (its
  // first updates learn the car's speed, results/real_data/README.md) the prediction is within
  // a few centimetres of the true motion.
  const std::string dir = SharedData() + "/kitti_excerpt_1";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " absent (the real excerpts are not part of the repository)";
  const auto source = OpenStereoImages(dir);
  const std::unique_ptr<PoseTracker> tracker =
      CreateTracker("trifocal_line_ekf", KittiTrackerOptions("trifocal_line_ekf"), "datasets.json");
  StereoFrontEnd front_end(FrontEndOptions(), source->rig());
  ImageTracker image_tracker(front_end, *tracker, source->rig());
  const Trajectory& truth = source->ground_truth();
  constexpr int kFrames = 8;
  int predicted = 0, tracked = 0;
  for (int k = 0; k < kFrames; ++k) {
    const std::optional<Rigid3d> motion = image_tracker.next_motion();
    const StereoImages images = source->Read(k);
    const ImageTrackingStep step = image_tracker.Step(images.left, images.right, images.time);
    ASSERT_TRUE(step.output.cam_from_world.translation.allFinite());
    if (k < 2) continue;  // no update yet before frame 1, so no prediction for it
    ASSERT_TRUE(motion.has_value()) << "frame " << k;
    const Rigid3d true_motion = truth[k].world_from_cam.Inverse() * truth[k - 1].world_from_cam;
    if (k >= 4) {
      EXPECT_LT((motion->translation - true_motion.translation).norm(), 0.1) << "frame " << k;
    }
    predicted += front_end.last_stats().predicted;
    tracked += front_end.last_stats().tracked;
  }
  EXPECT_GE(predicted, 0.6 * tracked) << predicted << " of " << tracked;
}

}  // namespace
}  // namespace slt
