#include "frontend/stereo_rectification.h"

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace slt {
namespace {

cv::Matx33d ToCv(const Eigen::Matrix3d& m) {
  cv::Matx33d out;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out(r, c) = m(r, c);
  }
  return out;
}

bool IsIdealRectifiedRig(const DistortedStereoCalibration& c) {
  const Eigen::Vector3d& t = c.right_from_left.translation;
  return IsZero(c.left_distortion) && IsZero(c.right_distortion) &&
         (c.right_from_left.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-12 &&
         std::abs(t.y()) < 1e-12 * t.norm() && std::abs(t.z()) < 1e-12 * t.norm() && c.left.fy == c.right.fy &&
         c.left.cy == c.right.cy;
}

}  // namespace

StereoRectifier::StereoRectifier(const DistortedStereoCalibration& c) {
  rig_.width = c.width;
  rig_.height = c.height;
  rig_.left = c.left;
  rig_.right = c.right;
  rig_.right_from_left = c.right_from_left;
  if (IsIdealRectifiedRig(c)) return;
  const Eigen::Vector3d& t = c.right_from_left.translation;
  if (!(std::abs(t.x()) > 0.5 * t.norm())) {
    throw std::invalid_argument("the baseline is not mostly along x: horizontal stereo rectification needs a side-by-side rig");
  }
  active_ = true;
  const cv::Matx33d k[2] = {ToCv(c.left.K()), ToCv(c.right.K())};
  const cv::Vec4d d[2] = {{c.left_distortion[0], c.left_distortion[1], c.left_distortion[2], c.left_distortion[3]},
                          {c.right_distortion[0], c.right_distortion[1], c.right_distortion[2], c.right_distortion[3]}};
  const cv::Size size(c.width, c.height);
  cv::Matx33d r[2];
  cv::Matx34d p[2];
  cv::Matx44d q;
  // X_right = R X_left + T, OpenCV's (R, T) of stereoRectify.
  cv::stereoRectify(k[0], d[0], k[1], d[1], size, ToCv(c.right_from_left.rotation), cv::Vec3d(t.x(), t.y(), t.z()), r[0],
                    r[1], p[0], p[1], q, cv::CALIB_ZERO_DISPARITY, /*alpha=*/0.0, size);
  for (int i = 0; i < 2; ++i) {
    cv::initUndistortRectifyMap(k[i], d[i], r[i], p[i], size, CV_16SC2, map_xy_[i], map_fraction_[i]);
  }
  rig_.left = PinholeCamera{p[0](0, 0), p[0](1, 1), p[0](0, 2), p[0](1, 2)};
  rig_.right = PinholeCamera{p[1](0, 0), p[1](1, 1), p[1](0, 2), p[1](1, 2)};
  // P_right = K [I | (Tx, 0, 0)] with P_right(0, 3) = fx Tx: the right centre at -Tx on x.
  rig_.right_from_left = Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(p[1](0, 3) / p[1](0, 0), 0.0, 0.0));
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) rectified_from_left_(row, col) = r[0](row, col);
  }
  rig_.Check();
}

cv::Mat StereoRectifier::Rectify(const cv::Mat& image, int camera) const {
  if (!active_) return image;
  cv::Mat out;
  cv::remap(image, out, map_xy_[camera], map_fraction_[camera], cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return out;
}

}  // namespace slt
