// Pinhole cameras and the stereo rig.
//
// Pixel coordinates: u to the right, v down, origin at the centre of the top-left pixel.
// Camera axes: x right, y down, z forward (docs/conventions.md).
#pragma once

#include <Eigen/Core>
#include <string>

#include "geometry/rigid3.h"

namespace slt {

struct PinholeCamera {
  double fx = 848.7;
  double fy = 848.7;
  double cx = 320.0;
  double cy = 240.0;

  Eigen::Matrix3d K() const;
  // Pixel -> normalised image coordinates (z = 1 plane) and back.
  Eigen::Vector2d PixelToNormalized(const Eigen::Vector2d& pixel) const {
    return {(pixel.x() - cx) / fx, (pixel.y() - cy) / fy};
  }
  Eigen::Vector2d NormalizedToPixel(const Eigen::Vector2d& xy) const {
    return {fx * xy.x() + cx, fy * xy.y() + cy};
  }
  // Projects a point in camera coordinates; the caller checks z > 0.
  Eigen::Vector2d Project(const Eigen::Vector3d& point_in_cam) const {
    return NormalizedToPixel(point_in_cam.head<2>() / point_in_cam.z());
  }
  // Throws std::invalid_argument naming `what` when a value is not finite or a focal <= 0.
  void Check(const std::string& what = "camera") const;
};

struct StereoRig {
  int width = 640;
  int height = 480;
  PinholeCamera left;
  PinholeCamera right;
  // X_right = right_from_left * X_left. The paper's E (eq. 2). Default: baseline 0.1 m along +x,
  // so the right camera's centre is at x = +0.1 m in the left frame and t = (-0.1, 0, 0).
  Rigid3d right_from_left{Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.1, 0.0, 0.0)};

  double Baseline() const { return right_from_left.translation.norm(); }
  bool InImage(const Eigen::Vector2d& pixel) const {
    return pixel.x() >= 0.0 && pixel.y() >= 0.0 && pixel.x() <= width - 1.0 &&
           pixel.y() <= height - 1.0;
  }
  // Throws std::invalid_argument with a reason when the rig is not usable.
  void Check() const;
};

}  // namespace slt
