// The image front end paired with a pose tracker: one stereo pair in, the tracker's pose out.
// The one loop body of track_images, measure_frontend and the front end's tests: the tracker
// says whether the next frame should bring new lines (PoseTracker::WantsNewFeatures), the front
// end tracks (and detects when asked), the tracker takes the frame.
#pragma once

#include <opencv2/core.hpp>

#include "frontend/stereo_frontend.h"
#include "methods/pose_tracker.h"

namespace slt {

struct ImageTrackingStep {
  const StereoFrame* frame = nullptr;  // the front end's output (valid until the next Step)
  TrackerOutput output;
  double tracker_seconds = 0.0;
};

class ImageTracker {
 public:
  // Resets the tracker with the front end's rig. Both must outlive this object.
  ImageTracker(StereoFrontEnd& front_end, PoseTracker& tracker, const StereoRig& rig);
  ImageTrackingStep Step(const cv::Mat& left, const cv::Mat& right, double time);

 private:
  StereoFrontEnd& front_end_;
  PoseTracker& tracker_;
};

}  // namespace slt
