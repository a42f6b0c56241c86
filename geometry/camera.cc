#include "geometry/camera.h"

#include <cmath>
#include <stdexcept>

namespace slt {

Eigen::Matrix3d PinholeCamera::K() const {
  Eigen::Matrix3d k;
  k << fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0;
  return k;
}

void PinholeCamera::Check(const std::string& what) const {
  if (!std::isfinite(fx) || !std::isfinite(fy) || !std::isfinite(cx) || !std::isfinite(cy)) {
    throw std::invalid_argument(what + ": intrinsics must be finite");
  }
  if (fx <= 0.0 || fy <= 0.0) {
    throw std::invalid_argument(what + ": focal lengths fx, fy must be positive");
  }
}

void StereoRig::Check() const {
  if (width <= 0 || height <= 0) {
    throw std::invalid_argument("rig: width and height must be positive");
  }
  left.Check("rig.left");
  right.Check("rig.right");
  const Eigen::Matrix3d& r = right_from_left.rotation;
  if (!r.allFinite() || !right_from_left.translation.allFinite()) {
    throw std::invalid_argument("rig.right_from_left: R and t must be finite");
  }
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-6 || r.determinant() < 0.0) {
    throw std::invalid_argument("rig.right_from_left.R: not a rotation matrix");
  }
  if (Baseline() <= 0.0) {
    throw std::invalid_argument("rig.right_from_left.t: baseline must be non-zero");
  }
}

}  // namespace slt
