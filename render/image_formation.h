// The camera's effects on the scene radiance (render/rasterizer.h), in the order a sensor
// applies them (docs/rendering.md):
//
//   level(u, v) = kWhiteLevel * gain_k * (1 - vignetting * r(u, v)^2) * radiance(u, v)
//   blurred     = Gaussian(defocus_blur_px) * level
//   noisy       = blurred + sqrt(read_noise^2 + shot_noise * blurred) * N(0, 1)
//   pixel       = round(noisy), saturated to [0, 255]
//
// with r the distance from the image centre over the distance to a corner, gain_k the frame's
// exposure gain (ExposureGain) and N(0, 1) drawn per pixel from the image's own generator
// (12 random bits index a table of 4096 normal quantiles: Gaussian to 1/4096 in probability).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "simulator/simulation_config.h"

namespace slt {

// The grey level of radiance 1 at gain 1 in the image centre.
constexpr double kWhiteLevel = 240.0;

// Gain of frame k: (1 + exposure_variation * wave(k)) * AutoExposureGain(k), wave a sum of two
// slow sinusoids (periods 60-180 frames, random phases from the "exposure" stream of `seed`)
// within [-1, 1]; both cameras of a frame share it (a synchronised rig).
double ExposureGain(const ImageConfig& config, std::uint64_t seed, int frame);
// The auto-exposure's steps (ImageConfig::auto_exposure_step; 1 when off): at frames spaced
// by auto_exposure_interval_frames times U(0.5, 1.5) the gain's target is multiplied by
// U(1 - step, 1 + step) (divided instead when it would leave [1 - 2 step, 1 + 2 step]) and the
// gain moves to it linearly over auto_exposure_ramp_frames frames, from the "auto_exposure"
// stream of `seed`.
double AutoExposureGain(const ImageConfig& config, std::uint64_t seed, int frame);

// The 8-bit image (CV_8UC1) from a radiance image (CV_32FC1). `noise_key` seeds the image's
// noise generator: the same key gives the same image.
cv::Mat FormImage(const cv::Mat& radiance, const ImageConfig& config, double gain, std::uint64_t noise_key);

}  // namespace slt
