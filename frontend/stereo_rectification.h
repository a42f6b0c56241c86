// Undistortion and stereo rectification of a calibrated pair, so that the tracker sees the
// ideal rig its models assume (docs/datasets.md): two pinhole cameras without distortion, the
// same orientation, the right camera's centre on the left camera's x axis.
//
// The input's lens model is radial-tangential (geometry/distortion.h), as EuRoC calibrates it.
// The rectified rig comes from cv::stereoRectify (Bouguet's method: each camera rotated by half
// the relative rotation, then both about their common baseline) with alpha = 0, so that every
// pixel of the rectified images sees the scene (no black border, which would be detected as
// lines). The rectified left camera is rotated from the original one by rectified_from_left:
// X_rectified = rectified_from_left * X_left; a pose of the original left camera maps as
// world_from_rectified = world_from_left * rectified_from_left^T.
#pragma once

#include <opencv2/core.hpp>

#include "geometry/camera.h"
#include "geometry/distortion.h"

namespace slt {

struct DistortedStereoCalibration {
  int width = 0, height = 0;
  PinholeCamera left, right;
  RadialTangential left_distortion{}, right_distortion{};
  Rigid3d right_from_left;
};

class StereoRectifier {
 public:
  // Throws std::invalid_argument when the rig is unusable (cv::stereoRectify's preconditions,
  // a baseline that is not mostly along x).
  explicit StereoRectifier(const DistortedStereoCalibration& calibration);

  // False when the input is already an ideal rectified rig (no distortion, the same rotation,
  // baseline along x, equal fy and cy): the images then pass through unchanged, bit for bit.
  bool active() const { return active_; }
  const StereoRig& rig() const { return rig_; }
  const Eigen::Matrix3d& rectified_from_left() const { return rectified_from_left_; }
  // The rectified image of `camera` (0 = left, 1 = right); bilinear interpolation. Returns the
  // input itself when !active().
  cv::Mat Rectify(const cv::Mat& image, int camera) const;

 private:
  bool active_ = false;
  StereoRig rig_;
  Eigen::Matrix3d rectified_from_left_ = Eigen::Matrix3d::Identity();
  cv::Mat map_xy_[2], map_fraction_[2];
};

}  // namespace slt
