#include "frontend/image_tracking.h"

#include <chrono>

namespace slt {

ImageTracker::ImageTracker(StereoFrontEnd& front_end, PoseTracker& tracker, const StereoRig& rig)
    : front_end_(front_end), tracker_(tracker) {
  tracker_.Reset(rig);
}

ImageTrackingStep ImageTracker::Step(const cv::Mat& left, const cv::Mat& right, double time) {
  ImageTrackingStep step;
  step.frame = &front_end_.Process(left, right, time, tracker_.WantsNewFeatures());
  const auto t0 = std::chrono::steady_clock::now();
  step.output = tracker_.Track(*step.frame);
  step.tracker_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return step;
}

}  // namespace slt
