#include "frontend/image_tracking.h"

#include <chrono>

namespace slt {

ImageTracker::ImageTracker(StereoFrontEnd& front_end, PoseTracker& tracker, const StereoRig& rig)
    : front_end_(front_end), tracker_(tracker) {
  tracker_.Reset(rig);
}

ImageTrackingStep ImageTracker::Step(const cv::Mat& left, const cv::Mat& right, double time) {
  ImageTrackingStep step;
  step.frame = &front_end_.Process(left, right, time, tracker_.WantsNewFeatures(), next_motion_, measured_motion_);
  const auto t0 = std::chrono::steady_clock::now();
  step.output = tracker_.Track(*step.frame);
  step.tracker_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const Rigid3d& pose = step.output.cam_from_world;
  const bool measured = step.output.status != TrackingStatus::kLost;
  measured_motion_.reset();
  if (measured && last_measured_) measured_motion_ = pose * last_measured_->Inverse();
  next_motion_ = measured_motion_;
  if (const std::optional<Rigid3d> predicted = tracker_.PredictNext()) next_motion_ = *predicted * pose.Inverse();
  if (measured) {
    last_measured_ = pose;
  } else {
    last_measured_.reset();
  }
  return step;
}

}  // namespace slt
