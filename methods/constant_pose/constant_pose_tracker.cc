#include "methods/constant_pose/constant_pose_tracker.h"

#include "common/json_reader.h"

namespace slt {

void ConstantPoseTracker::Reset(const StereoRig& rig) {
  rig.Check();
  started_ = false;
}

TrackerOutput ConstantPoseTracker::Track(const StereoFrame& frame) {
  TrackerOutput out;
  out.status = started_ ? TrackingStatus::kTracking : TrackingStatus::kNewReference;
  out.features_available = static_cast<int>(frame.left.size());
  started_ = true;
  return out;
}

TrackerInfo ConstantPoseTrackerInfo() {
  TrackerInfo info;
  info.name = "constant_pose";
  info.description = "Identity pose for every frame (plumbing test only)";
  info.plumbing_only = true;
  info.create = [](const nlohmann::json& options, const std::string& where) {
    JsonReader reader(options, where);
    reader.RejectUnknownKeys();
    return std::make_unique<ConstantPoseTracker>();
  };
  return info;
}

}  // namespace slt
