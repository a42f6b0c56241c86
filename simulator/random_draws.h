// Random variates for the simulator, written out here rather than taken from <random>'s
// distributions: those are implementation-defined, and a benchmark's synthetic data should be
// the same whichever standard library built it.
//
// Two kinds of stream (docs/simulation.md, "Seeding"):
// - sequential streams (common/random.h, mt19937_64) for the scene and the motion, drawn once
//   per sequence in a fixed order;
// - keyed streams for the per-observation draws (noise, sliding extents, outliers): the draws of
//   one observation come from a SplitMix64 generator started at a hash of (stream key, frame,
//   camera, line id). An observation's noise then depends on nothing else: not on which other
//   lines were visible, clipped or cut by max_features, nor on the noise level (the variates are
//   drawn at unit scale and scaled afterwards).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/random.h"

namespace slt {

// SplitMix64 (Steele, Lea, Flood 2014): a tiny generator that is cheap to start anywhere.
// MixSeed is its output function, so successive calls give the reference SplitMix64 sequence.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t state) : state_(state) {}
  std::uint64_t operator()() {
    const std::uint64_t out = MixSeed(state_);
    state_ += 0x9e3779b97f4a7c15ULL;
    return out;
  }

 private:
  std::uint64_t state_;
};

// A named stream whose draws are addressed by (frame, camera, id) instead of by order:
// stream.Image(frame, camera).At(id) starts the generator of one observation.
class KeyedStream {
 public:
  // The draws of one image; cheap to keep for a whole image (one hash per observation).
  class ImageKey {
   public:
    explicit ImageKey(std::uint64_t key) : key_(key) {}
    SplitMix64 At(std::uint64_t id) const { return SplitMix64(MixSeed(key_ ^ id)); }

   private:
    std::uint64_t key_;
  };

  KeyedStream(std::uint64_t seed, std::string_view name) : key_(StreamSeed(seed, name)) {}
  ImageKey Image(std::uint64_t frame, std::uint64_t camera) const {
    return ImageKey(MixSeed(MixSeed(key_ ^ frame) ^ camera));
  }

 private:
  std::uint64_t key_;
};

// Uniform in [0, 1) with 53 random bits.
template <typename Generator>
double Uniform01(Generator& g) {
  return static_cast<double>(g() >> 11) * 0x1.0p-53;
}

template <typename Generator>
double Uniform(Generator& g, double lo, double hi) {
  return lo + (hi - lo) * Uniform01(g);
}

// Uniform integer in [0, n), n > 0.
template <typename Generator>
std::size_t UniformIndex(Generator& g, std::size_t n) {
  const auto i = static_cast<std::size_t>(Uniform01(g) * static_cast<double>(n));
  return i < n ? i : n - 1;
}

// Two independent standard normal variates (Box-Muller, from two uniforms).
template <typename Generator>
Eigen::Vector2d StandardNormalPair(Generator& g) {
  const double u1 = 1.0 - Uniform01(g);  // (0, 1]: the logarithm stays finite
  const double u2 = Uniform01(g);
  const double r = std::sqrt(-2.0 * std::log(u1));
  const double a = 2.0 * M_PI * u2;
  return {r * std::cos(a), r * std::sin(a)};
}

// A unit vector uniform on the sphere (Archimedes: z uniform in [-1, 1]); always two draws.
template <typename Generator>
Eigen::Vector3d UniformUnitVector(Generator& g) {
  const double z = Uniform(g, -1.0, 1.0);
  const double a = Uniform(g, 0.0, 2.0 * M_PI);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(a), r * std::sin(a), z};
}

}  // namespace slt
