#include <chrono>
#include <sstream>
#include <stdexcept>

#include "methods/constant_pose/constant_pose_tracker.h"
#include "methods/elqursh_three_line/elqursh_three_line.h"
#include "methods/pose_tracker.h"
#include "methods/taylor_line_sfm/taylor_line_sfm.h"
#include "methods/trifocal_line_ekf/trifocal_line_ekf.h"
#include "methods/yu_point_ekf/yu_point_ekf.h"

namespace slt {

const std::vector<TrackerInfo>& RegisteredTrackers() {
  // One line per tracker.
  static const std::vector<TrackerInfo> trackers = {
      TrifocalLineEkfInfo(),
      YuPointEkfInfo(),
      TaylorLineSfmInfo(),
      ElqurshThreeLineInfo(),
      ConstantPoseTrackerInfo(),
  };
  return trackers;
}

std::vector<std::string> RegisteredTrackerNames(bool include_plumbing) {
  std::vector<std::string> names;
  for (const TrackerInfo& info : RegisteredTrackers()) {
    if (include_plumbing || !info.plumbing_only) names.push_back(info.name);
  }
  return names;
}

const TrackerInfo& FindTracker(const std::string& name) {
  for (const TrackerInfo& info : RegisteredTrackers()) {
    if (info.name == name) return info;
  }
  std::ostringstream known;
  for (const TrackerInfo& info : RegisteredTrackers()) known << " " << info.name;
  throw std::invalid_argument("unknown method '" + name + "' (known:" + known.str() + ")");
}

std::unique_ptr<PoseTracker> CreateTracker(const std::string& name, const nlohmann::json& options,
                                           const std::string& where) {
  return FindTracker(name).create(options, where);
}

TrackedFrame TrackFrame(PoseTracker& tracker, const StereoFrame& frame) {
  const auto start = std::chrono::steady_clock::now();
  TrackedFrame tracked{tracker.Track(frame), 0.0, frame.time};
  tracked.time_us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  return tracked;
}

std::vector<TrackedFrame> TrackSequence(PoseTracker& tracker, const StereoSequence& sequence) {
  std::vector<TrackedFrame> frames;
  frames.reserve(sequence.frames.size());
  tracker.Reset(sequence.rig);
  for (const StereoFrame& frame : sequence.frames) frames.push_back(TrackFrame(tracker, frame));
  return frames;
}

}  // namespace slt
