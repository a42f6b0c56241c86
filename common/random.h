// Seeded, independent random streams.
//
// Each source of randomness (scene, motion, image noise, outliers, ...) draws from its own
// stream, derived from a seed and the stream's name with SplitMix64, so that changing one
// source (say the noise level) leaves the others bit-identical, and trials are reproducible
// whatever the order or thread they run in.
#pragma once

#include <cstdint>
#include <random>
#include <string_view>

namespace slt {

// SplitMix64 finaliser: a bijective mix of a 64-bit value.
inline std::uint64_t MixSeed(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// FNV-1a of the stream name, so streams are named, not numbered.
inline std::uint64_t HashName(std::string_view name) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (char c : name) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001b3ULL;
  return h;
}

// The seed of stream `name` for base `seed`.
inline std::uint64_t StreamSeed(std::uint64_t seed, std::string_view name) {
  return MixSeed(MixSeed(seed) ^ HashName(name));
}

using RandomStream = std::mt19937_64;

inline RandomStream MakeStream(std::uint64_t seed, std::string_view name) {
  return RandomStream(StreamSeed(seed, name));
}

// The seed of trial `trial` of an experiment whose base seed is `seed`.
inline std::uint64_t TrialSeed(std::uint64_t seed, std::uint64_t trial) {
  return MixSeed(seed * 0x100000001b3ULL + trial);
}

}  // namespace slt
