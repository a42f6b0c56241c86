// The image front end paired with a pose tracker: one stereo pair in, the tracker's pose out.
// The one loop body of track_images, measure_frontend and the front end's tests: the tracker
// says whether the next frame should bring new lines (PoseTracker::WantsNewFeatures) and where
// it expects the camera (PoseTracker::PredictNext), the front end tracks (its optical flow
// seeded by the predicted motion, and detects when asked), the tracker takes the frame.
//
// The predicted motion handed to the front end is next_from_previous = P * M_t^-1, with M_t
// the tracker's pose at the last frame and P its PredictNext(); a tracker without a prediction
// gets the constant-velocity extrapolation of its last two poses, M_t M_t-1^-1, when both were
// measured (not lost); otherwise the front end has no prediction.
#pragma once

#include <opencv2/core.hpp>
#include <optional>

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

  // The motion handed to the front end for the next pair (none: no prediction).
  const std::optional<Rigid3d>& next_motion() const { return next_motion_; }

 private:
  StereoFrontEnd& front_end_;
  PoseTracker& tracker_;
  std::optional<Rigid3d> next_motion_;
  // The motion between the last two frames as the tracker measured it (both not lost).
  std::optional<Rigid3d> measured_motion_;
  // The last measured (not lost) pose, for the constant-velocity extrapolation.
  std::optional<Rigid3d> last_measured_;
};

}  // namespace slt
