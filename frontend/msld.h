// The mean-standard deviation line descriptor, MSLD (Wang, Wu & Hu, "MSLD: A robust descriptor
// for line matching", Pattern Recognition 42, 2009), which the paper uses for stereo matching
// (Sec. 3.1).
//
// For an oriented segment a -> b (line_detection.h: direction d, normal n = (-d_v, d_u)) of
// length L, the line pixels are p_i = a + i d, i = 0 .. N-1, N = floor(L) + 1. Each has a pixel
// support region of 9 sub-regions side by side across the line, each 5 x 5 pixels:
//   q(i, s, c) = p_i + s d + c n,   s = -2 .. 2 (along),  c = -22 .. 22 (across),
// sub-region j = 0 .. 8 holding c = -22 + 5j .. -18 + 5j. The gradient at q, on the image
// smoothed by a Gaussian of sigma = 1.2 px (a Gaussian derivative), is projected on the line's
// direction and normal by central differences one pixel apart:
//   g_d = (I(q + d) - I(q - d)) / 2,   g_n = (I(q + n) - I(q - n)) / 2   (I bilinear),
// and weighted by the Gaussian w(c) = exp(-c^2 / (2 sigma_w^2)), sigma_w = 22.5 px (half the
// region's width, as in the MSLD paper). Per sub-region the four sums
//   V_j = [sum w max(g_n, 0), sum w max(-g_n, 0), sum w max(g_d, 0), sum w max(-g_d, 0)]
// over its 25 points make the 36-vector V(p_i) of the line pixel, a column of the gradient
// description matrix. The descriptor is [mean_i V(p_i) / |mean|, std_i V(p_i) / |std|] (72
// values), clipped at 0.4 and renormalised to unit length: invariant to affine changes of the
// intensity and to the line's length.
//
// The extractor computes it vectorised over the line's pixels: the smoothed image is resampled
// once per line into a line-aligned (N + 6) x 47 patch (rows along the line, columns across),
// in which g_d and g_n are differences of neighbouring patch samples, and the 5 x 5 sums are box
// sums along rows and columns. msld_test.cc checks it against the definition above evaluated
// point by point.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "geometry/line2d.h"

namespace slt {

constexpr int kMsldSize = 72;
using MsldDescriptor = Eigen::Matrix<float, kMsldSize, 1>;

// Pixel support region geometry (see above).
struct MsldLayout {
  static constexpr int kSubRegions = 9;
  static constexpr int kSubRegionSize = 5;
  static constexpr int kHalfWidth = kSubRegions * kSubRegionSize / 2;  // 22: c = -22 .. 22
  static constexpr int kHalfLength = kSubRegionSize / 2;               // 2:  s = -2 .. 2
  static constexpr double kSmoothingSigma = 1.2;
  static constexpr double kWeightSigma = 22.5;
  static constexpr float kClip = 0.4f;
};

class MsldExtractor {
 public:
  // Smooths the image (8-bit grey) once; descriptors of its lines follow.
  void SetImage(const cv::Mat& grey);
  const cv::Mat& smoothed() const { return smoothed_; }
  // The descriptor of an oriented segment (at least 2 px long); false for a shorter one.
  bool Compute(const Segment2d& segment, MsldDescriptor* descriptor);

 private:
  cv::Mat smoothed_;  // CV_32FC1
  // Workspace, reused from line to line.
  std::vector<float> patch_, row_sums_, column_sums_;
};

}  // namespace slt
