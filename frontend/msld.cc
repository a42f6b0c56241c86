#include "frontend/msld.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace slt {
namespace {

constexpr int kCols = 2 * MsldLayout::kHalfWidth + 3;  // 47: c = -23 .. 23
constexpr int kFeatures = 4 * MsldLayout::kSubRegions;  // 36 per line pixel

const std::array<float, 2 * MsldLayout::kHalfWidth + 1>& Weights() {
  static const auto weights = [] {
    std::array<float, 2 * MsldLayout::kHalfWidth + 1> w{};
    for (int c = -MsldLayout::kHalfWidth; c <= MsldLayout::kHalfWidth; ++c) {
      w[c + MsldLayout::kHalfWidth] = static_cast<float>(
          std::exp(-c * c / (2.0 * MsldLayout::kWeightSigma * MsldLayout::kWeightSigma)));
    }
    return w;
  }();
  return weights;
}

}  // namespace

void MsldExtractor::SetImage(const cv::Mat& grey) {
  cv::Mat f;
  grey.convertTo(f, CV_32F);
  cv::GaussianBlur(f, smoothed_, cv::Size(0, 0), MsldLayout::kSmoothingSigma, MsldLayout::kSmoothingSigma,
                   cv::BORDER_REPLICATE);
}

bool MsldExtractor::Compute(const Segment2d& segment, MsldDescriptor* descriptor) {
  const Eigen::Vector2d a = segment.head<2>(), b = segment.tail<2>();
  const double length = (b - a).norm();
  if (length < 2.0 || smoothed_.empty()) return false;
  const int n_pixels = static_cast<int>(std::floor(length)) + 1;
  const int rows = n_pixels + 6;  // s from -3 to N + 2: the support (+-2) plus the difference (+-1)
  const float dx = static_cast<float>((b.x() - a.x()) / length), dy = static_cast<float>((b.y() - a.y()) / length);
  const float nx = -dy, ny = dx;

  // 1. The line-aligned patch: patch(r, k) = I(a + (r - 3) d + (k - 23) n), bilinear.
  patch_.resize(static_cast<size_t>(rows) * kCols);
  const int w = smoothed_.cols, h = smoothed_.rows;
  const float* image = smoothed_.ptr<float>(0);
  const size_t stride = smoothed_.step1();
  // The patch's corners inside [0, w - 2] x [0, h - 2]: no sample needs clamping (the common
  // case; the loop below then has no branches).
  const auto inside = [&](float u, float v) { return u >= 0.0f && v >= 0.0f && u < w - 2 && v < h - 2; };
  const float u00 = static_cast<float>(a.x()) - 3 * dx - 23 * nx, v00 = static_cast<float>(a.y()) - 3 * dy - 23 * ny;
  const float along = static_cast<float>(rows - 1), across = static_cast<float>(kCols - 1);
  const bool all_inside = inside(u00, v00) && inside(u00 + along * dx, v00 + along * dy) &&
                          inside(u00 + across * nx, v00 + across * ny) &&
                          inside(u00 + along * dx + across * nx, v00 + along * dy + across * ny);
  // I(u0 + fu, v0 + fv), bilinear (pixel (u0, v0) and its neighbours inside the image).
  const auto bilinear = [&](int u0, int v0, float fu, float fv) {
    const float* p0 = image + v0 * stride + u0;
    const float* p1 = p0 + stride;
    return (1 - fv) * ((1 - fu) * p0[0] + fu * p0[1]) + fv * ((1 - fu) * p1[0] + fu * p1[1]);
  };
  for (int r = 0; r < rows; ++r) {
    const float base_u = static_cast<float>(a.x()) + (r - 3) * dx - 23 * nx;
    const float base_v = static_cast<float>(a.y()) + (r - 3) * dy - 23 * ny;
    float* out = &patch_[static_cast<size_t>(r) * kCols];
    if (all_inside) {
      for (int k = 0; k < kCols; ++k) {
        const float u = base_u + k * nx, v = base_v + k * ny;
        const int u0 = static_cast<int>(u), v0 = static_cast<int>(v);
        out[k] = bilinear(u0, v0, u - u0, v - v0);
      }
      continue;
    }
    for (int k = 0; k < kCols; ++k) {
      float u = base_u + k * nx, v = base_v + k * ny;
      u = u < 0.0f ? 0.0f : (u > w - 1 ? static_cast<float>(w - 1) : u);
      v = v < 0.0f ? 0.0f : (v > h - 1 ? static_cast<float>(h - 1) : v);
      int u0 = static_cast<int>(u), v0 = static_cast<int>(v);
      u0 = u0 > w - 2 ? w - 2 : u0;
      v0 = v0 > h - 2 ? h - 2 : v0;
      out[k] = bilinear(u0, v0, u - u0, v - v0);
    }
  }

  // 2. Per patch row r (= line position s, from -2 to N + 1), the 36 sums over each
  // sub-region's 5 columns of the weighted, signed gradient projections.
  const int sum_rows = n_pixels + 4;
  row_sums_.assign(static_cast<size_t>(sum_rows) * kFeatures, 0.0f);
  const auto& weight = Weights();
  for (int r = 0; r < sum_rows; ++r) {
    const float* up = &patch_[static_cast<size_t>(r) * kCols];      // s - 1
    const float* mid = up + kCols;                                   // s
    const float* down = mid + kCols;                                 // s + 1
    float* out = &row_sums_[static_cast<size_t>(r) * kFeatures];
    for (int j = 0; j < MsldLayout::kSubRegions; ++j) {
      float np = 0, nm = 0, dp = 0, dm = 0;
      for (int c = 5 * j; c < 5 * j + 5; ++c) {
        const int k = c + 1;  // patch column of c - 22
        const float gn = 0.5f * (mid[k + 1] - mid[k - 1]) * weight[c];
        const float gd = 0.5f * (down[k] - up[k]) * weight[c];
        np += gn > 0 ? gn : 0.0f;
        nm += gn < 0 ? -gn : 0.0f;
        dp += gd > 0 ? gd : 0.0f;
        dm += gd < 0 ? -gd : 0.0f;
      }
      out[4 * j + 0] = np;
      out[4 * j + 1] = nm;
      out[4 * j + 2] = dp;
      out[4 * j + 3] = dm;
    }
  }

  // 3. V(p_i) = sum of rows i .. i + 4 (s = -2 .. 2 around pixel i), as a running sum; mean
  // and second moment over the line pixels.
  float window[kFeatures] = {0};
  for (int r = 0; r < 5; ++r) {
    for (int f = 0; f < kFeatures; ++f) window[f] += row_sums_[static_cast<size_t>(r) * kFeatures + f];
  }
  double sum[kFeatures] = {0}, sum_sq[kFeatures] = {0};
  for (int i = 0; i < n_pixels; ++i) {
    if (i > 0) {
      const float* add = &row_sums_[static_cast<size_t>(i + 4) * kFeatures];
      const float* sub = &row_sums_[static_cast<size_t>(i - 1) * kFeatures];
      for (int f = 0; f < kFeatures; ++f) window[f] += add[f] - sub[f];
    }
    for (int f = 0; f < kFeatures; ++f) {
      sum[f] += window[f];
      sum_sq[f] += static_cast<double>(window[f]) * window[f];
    }
  }
  Eigen::Matrix<double, kFeatures, 1> mean, std_dev;
  for (int f = 0; f < kFeatures; ++f) {
    mean[f] = sum[f] / n_pixels;
    std_dev[f] = std::sqrt(std::max(0.0, sum_sq[f] / n_pixels - mean[f] * mean[f]));
  }
  const double mean_norm = mean.norm(), std_norm = std_dev.norm();
  if (mean_norm > 0) mean /= mean_norm;
  if (std_norm > 0) std_dev /= std_norm;
  MsldDescriptor& out = *descriptor;
  out.head<kFeatures>() = mean.cast<float>();
  out.tail<kFeatures>() = std_dev.cast<float>();
  out = out.cwiseMin(MsldLayout::kClip);
  const float norm = out.norm();
  if (norm > 0) out /= norm;
  return true;
}

}  // namespace slt
