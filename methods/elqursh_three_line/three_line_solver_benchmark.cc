// Time of the Elqursh & Elgammal minimal solve as the tracker runs it per RANSAC sample: the
// four rotation candidates from a primitive configuration and, for each, the metric
// translation from the same three stereo lines (three_line_solver.h). Goal: <= 2 us.
#include <benchmark/benchmark.h>

#include <vector>

#include "methods/elqursh_three_line/three_line_test_data.h"

namespace slt {
namespace {

using namespace three_line_test;

struct Sample {
  PrimitiveConfigurationLines in_a, in_b;
  std::array<StereoLineConstraint, 3> constraints;
};

std::vector<Sample> MakeSamples() {
  std::mt19937_64 rng(1);
  std::vector<Sample> samples(64);
  for (Sample& s : samples) {
    const std::array<Line3, 3> lines = RandomPrimitiveConfiguration(rng);
    const Rigid3d b_from_a = RandomMotion(rng);
    s.in_a = Images(Rigid3d(), lines);
    s.in_b = Images(b_from_a, lines);
    for (int i = 0; i < 3; ++i) s.constraints[i] = Constraint(b_from_a, lines[i]);
  }
  return samples;
}

void BM_RotationCandidates(benchmark::State& state) {
  const std::vector<Sample> samples = MakeSamples();
  size_t next = 0;
  RotationCandidates candidates;
  for (auto _ : state) {
    const Sample& s = samples[next++ & 63];
    benchmark::DoNotOptimize(RotationFromPrimitiveConfiguration(s.in_a, s.in_b, 1e-6, &candidates));
    benchmark::DoNotOptimize(candidates);
  }
}
BENCHMARK(BM_RotationCandidates);

void BM_MinimalSolve(benchmark::State& state) {
  const std::vector<Sample> samples = MakeSamples();
  size_t next = 0;
  RotationCandidates candidates;
  std::array<Eigen::Vector3d, 4> translations;
  for (auto _ : state) {
    const Sample& s = samples[next++ & 63];
    RotationFromPrimitiveConfiguration(s.in_a, s.in_b, 1e-6, &candidates);
    for (int i = 0; i < candidates.count; ++i) {
      TranslationFromStereoLines(candidates.b_from_a[i], kRightFromLeft, s.constraints.data(), 3, 1e-10,
                                 &translations[i]);
    }
    benchmark::DoNotOptimize(translations);
  }
}
BENCHMARK(BM_MinimalSolve);

}  // namespace
}  // namespace slt

BENCHMARK_MAIN();
