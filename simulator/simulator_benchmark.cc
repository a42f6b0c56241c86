// Time of one Simulate() call: experiments run thousands of trials, so the paper protocol
// (100 frames x 40 lines) should cost well under a millisecond.
#include <benchmark/benchmark.h>

#include "simulator/simulator.h"

namespace slt {
namespace {

void BM_Simulate(benchmark::State& state, const char* config_text) {
  SimulationConfig config = SimulationConfigFromJson(nlohmann::json::parse(config_text), "benchmark");
  for (auto _ : state) {
    ++config.seed;  // a new trial each time, as in an experiment
    benchmark::DoNotOptimize(Simulate(config));
  }
}

BENCHMARK_CAPTURE(BM_Simulate, paper_protocol, "{}")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Simulate, paper_sliding_clipped_outliers,
                  R"({"noise": {"endpoints": "sliding"}, "observation": {"clip_to_image": true},
                      "outliers": {"rate": 0.1}})")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Simulate, room_loop, R"({"scene": {"type": "room"}})")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Simulate, corridor_forward, R"({"scene": {"type": "corridor"}})")
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace slt

BENCHMARK_MAIN();
