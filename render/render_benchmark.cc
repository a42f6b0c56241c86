// Time to render one stereo pair (both 8-bit images, defaults of docs/rendering.md) of each
// scene at frame 0, on one core: `render_benchmark`. The counter per_pixel is the time per
// pixel of the pair (2 x width x height pixels). docs/rendering.md quotes the numbers.
#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>
#include <string>

#include "render/sequence_renderer.h"

namespace slt {
namespace {

// width, height 0: the scene's default rig.
void RenderPair(benchmark::State& state, const std::string& scene, int width, int height) {
  cv::setNumThreads(1);
  nlohmann::json j = {{"scene", {{"type", scene}}}, {"frames", 2}};
  SimulationConfig config = SimulationConfigFromJson(j, "benchmark");
  if (width > 0) {
    config.rig.width = width;
    config.rig.height = height;
    for (PinholeCamera* camera : {&config.rig.left, &config.rig.right}) {
      camera->cx = 0.5 * (width - 1);
      camera->cy = 0.5 * (height - 1);
    }
  }
  const SimulatedSequence sequence = Simulate(config);
  const SequenceRenderer renderer(sequence, config);
  for (auto _ : state) {
    benchmark::DoNotOptimize(renderer.Image(0, 0).data);
    benchmark::DoNotOptimize(renderer.Image(0, 1).data);
  }
  const double pixels = 2.0 * config.rig.width * config.rig.height;
  // Seconds per pixel of the pair, printed with an SI prefix (n = ns).
  state.counters["per_pixel"] =
      benchmark::Counter(pixels, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

BENCHMARK_CAPTURE(RenderPair, room_640x480, "room", 640, 480)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(RenderPair, room_752x480, "room", 752, 480)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(RenderPair, corridor_640x480, "corridor", 640, 480)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(RenderPair, paper_640x480, "paper", 640, 480)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(RenderPair, street_1241x376, "street", 0, 0)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace slt

BENCHMARK_MAIN();
