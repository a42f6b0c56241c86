// Bilinear sampling of grey images at sub-pixel positions, in the project's pixel convention
// (docs/conventions.md: pixel (u, v) is the centre of column u, row v; OpenCV's too). Positions
// outside are clamped to the border.
#pragma once

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>

namespace slt {

template <typename T>
inline float SampleBilinear(const cv::Mat& image, float u, float v) {
  const int w = image.cols, h = image.rows;
  u = std::clamp(u, 0.0f, static_cast<float>(w - 1));
  v = std::clamp(v, 0.0f, static_cast<float>(h - 1));
  const int u0 = std::min(static_cast<int>(u), w - 2 < 0 ? 0 : w - 2);
  const int v0 = std::min(static_cast<int>(v), h - 2 < 0 ? 0 : h - 2);
  const float a = u - u0, b = v - v0;
  const T* r0 = image.ptr<T>(v0);
  const T* r1 = image.ptr<T>(std::min(v0 + 1, h - 1));
  const int u1 = std::min(u0 + 1, w - 1);
  return (1 - b) * ((1 - a) * r0[u0] + a * r0[u1]) + b * ((1 - a) * r1[u0] + a * r1[u1]);
}

}  // namespace slt
