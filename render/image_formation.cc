#include "render/image_formation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "simulator/random_draws.h"

namespace slt {
namespace {

// Standard normal deviates at the midpoints of kNormalTableSize equal-probability bins: a
// 12-bit random index gives a normal variate without a logarithm or a sine per pixel.
constexpr int kNormalTableSize = 4096;

const std::array<float, kNormalTableSize>& NormalTable() {
  static const std::array<float, kNormalTableSize> table = [] {
    std::array<float, kNormalTableSize> t{};
    for (int i = 0; i < kNormalTableSize; ++i) {
      // Phi(x) = erfc(-x / sqrt(2)) / 2 = p, solved by bisection.
      const double p = (i + 0.5) / kNormalTableSize;
      double lo = -10.0, hi = 10.0;
      for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (lo + hi);
        (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
      }
      t[i] = static_cast<float>(0.5 * (lo + hi));
    }
    return t;
  }();
  return table;
}

}  // namespace

double AutoExposureGain(const ImageConfig& config, std::uint64_t seed, int frame) {
  if (config.auto_exposure_step <= 0.0) return 1.0;
  // Replays the steps up to `frame`: each image is a function of its frame alone.
  SplitMix64 g(StreamSeed(seed, "auto_exposure"));
  const double step = config.auto_exposure_step, lo = 1.0 - 2.0 * step, hi = 1.0 + 2.0 * step;
  double previous = 1.0, target = 1.0;
  double at = Uniform(g, 0.5, 1.5) * config.auto_exposure_interval_frames;  // frame of the next step
  while (at <= frame) {
    const double factor = Uniform(g, 1.0 - step, 1.0 + step);
    previous = target;
    // A step that would leave [1 - 2 step, 1 + 2 step] goes the other way: the camera's
    // controller keeps the brightness near its set point.
    target = previous * factor;
    if (target < lo || target > hi) target = previous / factor;
    const double next = at + Uniform(g, 0.5, 1.5) * config.auto_exposure_interval_frames;
    if (next > frame) break;
    at = next;
  }
  if (at > frame) return target;  // before the first step
  const double progress = std::min(1.0, (frame - std::ceil(at) + 1.0) / config.auto_exposure_ramp_frames);
  return previous + progress * (target - previous);
}

double ExposureGain(const ImageConfig& config, std::uint64_t seed, int frame) {
  SplitMix64 g(StreamSeed(seed, "exposure"));
  double wave = 0.0;
  for (const double amplitude : {0.6, 0.4}) {
    const double period = Uniform(g, 60.0, 180.0), phase = Uniform(g, 0.0, 2.0 * M_PI);
    wave += amplitude * std::sin(2.0 * M_PI * frame / period + phase);
  }
  return (1.0 + config.exposure_variation * wave) * AutoExposureGain(config, seed, frame);
}

cv::Mat FormImage(const cv::Mat& radiance, const ImageConfig& config, double gain, std::uint64_t noise_key) {
  const int width = radiance.cols, height = radiance.rows;
  cv::Mat level(height, width, CV_32FC1);
  const double cu = 0.5 * (width - 1), cv = 0.5 * (height - 1);
  const double inv_corner_sq = 1.0 / (cu * cu + cv * cv);
  for (int y = 0; y < height; ++y) {
    const float* in = radiance.ptr<float>(y);
    float* out = level.ptr<float>(y);
    const double dy2 = (y - cv) * (y - cv);
    for (int x = 0; x < width; ++x) {
      const double r2 = ((x - cu) * (x - cu) + dy2) * inv_corner_sq;
      out[x] = static_cast<float>(kWhiteLevel * gain * (1.0 - config.vignetting * r2) * in[x]);
    }
  }
  if (config.defocus_blur_px > 0.0) {
    cv::GaussianBlur(level, level, cv::Size(0, 0), config.defocus_blur_px, config.defocus_blur_px,
                     cv::BORDER_REFLECT_101);
  }
  cv::Mat image(height, width, CV_8UC1);
  const bool noisy = config.read_noise > 0.0 || config.shot_noise > 0.0;
  const std::array<float, kNormalTableSize>& normal = NormalTable();
  SplitMix64 g(noise_key);
  const float read_variance = static_cast<float>(config.read_noise * config.read_noise);
  const float shot = static_cast<float>(config.shot_noise);
  std::uint64_t bits = 0;
  int unused = 0;
  for (int y = 0; y < height; ++y) {
    const float* in = level.ptr<float>(y);
    unsigned char* out = image.ptr<unsigned char>(y);
    for (int x = 0; x < width; ++x) {
      float value = in[x];
      if (noisy) {
        // Five 12-bit table indices per 64-bit draw.
        if (unused == 0) {
          bits = g();
          unused = 5;
        }
        const float deviate = normal[bits & (kNormalTableSize - 1)];
        bits >>= 12;
        --unused;
        value += std::sqrt(read_variance + shot * std::max(0.0f, value)) * deviate;
      }
      out[x] = static_cast<unsigned char>(std::clamp(value, 0.0f, 255.0f) + 0.5f);
    }
  }
  return image;
}

}  // namespace slt
