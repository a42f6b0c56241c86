// A tracker that never moves: it reports the identity pose for every frame. It exists only to
// test the plumbing (I/O, drivers, the shared tracker suite) and as the trivial baseline that
// any real method must beat; it is marked plumbing_only in the registry.
#pragma once

#include "methods/pose_tracker.h"

namespace slt {

class ConstantPoseTracker final : public PoseTracker {
 public:
  void Reset(const StereoRig& rig) override;
  TrackerOutput Track(const StereoFrame& frame) override;
  nlohmann::json Options() const override { return nlohmann::json::object(); }

 private:
  bool started_ = false;
};

TrackerInfo ConstantPoseTrackerInfo();

}  // namespace slt
