// Per-stage speed of the image front end (issue 18: a steady frame <= 5 ms, a new-reference
// frame <= 30 ms for a 752 x 480 stereo pair, MSLD <= 20 us per 50-px line), single thread, on
// frames 0 and 1 of the rendered room loop at 752 x 480 (frontend_audit.h). docs/frontend.md
// quotes the numbers.
//
//   frontend_benchmark [--benchmark_repetitions=3]
#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>

#include "frontend/frontend_audit.h"
#include "frontend/stereo_frontend.h"
#include "render/sequence_renderer.h"
#include "simulator/simulation_config.h"

namespace slt {
namespace {

struct Pairs {
  StereoRig rig;
  cv::Mat images[2][2];  // [frame][camera]
};

const Pairs& RenderedPairs() {
  static const Pairs pairs = [] {
    cv::setNumThreads(1);
    const SimulationConfig config = SimulationConfigFromJson(RenderedRoomConfig(200, true), "frontend_benchmark");
    const SimulatedSequence sequence = Simulate(config);
    const SequenceRenderer renderer(sequence, config);
    Pairs p;
    p.rig = sequence.true_rig;
    for (int k = 0; k < 2; ++k) {
      for (int c = 0; c < 2; ++c) p.images[k][c] = renderer.Image(k, c);
    }
    return p;
  }();
  return pairs;
}

void BM_DetectOneImage(benchmark::State& state) {
  const LineDetectorType type = static_cast<LineDetectorType>(state.range(0));
  DetectionOptions options;
  options.detector = type;
  const std::unique_ptr<LineDetector> detector = MakeLineDetector(type);
  const cv::Mat& image = RenderedPairs().images[0][0];
  size_t lines = 0;
  for (auto _ : state) {
    const std::vector<ImageLine> detected = DetectLines(*detector, options, image);
    lines = detected.size();
    benchmark::DoNotOptimize(detected.data());
  }
  state.counters["lines"] = static_cast<double>(lines);
  state.SetLabel(EnumName(LineDetectorNames(), type));
}
BENCHMARK(BM_DetectOneImage)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);

// MSLD of 50-px lines: the detected lines of the left image at least 50 px long, cut to their
// middle 50 px. Time per line (items per second).
void BM_MsldPer50PxLine(benchmark::State& state) {
  const cv::Mat& image = RenderedPairs().images[0][0];
  const std::unique_ptr<LineDetector> detector = MakeLineDetector(LineDetectorType::kLsd);
  std::vector<Segment2d> segments;
  for (const ImageLine& line : DetectLines(*detector, DetectionOptions(), image)) {
    const double length = line.Length();
    if (length < 50.0) continue;
    const Eigen::Vector2d a = line.segment.head<2>(), d = (line.segment.tail<2>() - a) / length;
    const Eigen::Vector2d p = a + 0.5 * (length - 50.0) * d, q = p + 50.0 * d;
    segments.emplace_back(p.x(), p.y(), q.x(), q.y());
  }
  MsldExtractor extractor;
  extractor.SetImage(image);
  MsldDescriptor descriptor;
  for (auto _ : state) {
    for (const Segment2d& s : segments) {
      extractor.Compute(s, &descriptor);
      benchmark::DoNotOptimize(descriptor.data());
    }
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * segments.size()));
  state.counters["lines"] = static_cast<double>(segments.size());
}
BENCHMARK(BM_MsldPer50PxLine)->Unit(benchmark::kMicrosecond);

// Frame 1 after frame 0 (detected), with detection (a new-reference frame: track + filter +
// detect both images + MSLD + match) or without (a steady frame: track + filter).
void FrameAfterFirst(benchmark::State& state, bool detect) {
  const Pairs& pairs = RenderedPairs();
  const FrontEndOptions options;
  int live = 0;
  for (auto _ : state) {
    state.PauseTiming();
    StereoFrontEnd front_end(options, pairs.rig);
    front_end.Process(pairs.images[0][0], pairs.images[0][1], 0.0, true);
    state.ResumeTiming();
    const StereoFrame& frame = front_end.Process(pairs.images[1][0], pairs.images[1][1], 1.0, detect);
    live = static_cast<int>(frame.left.size());
  }
  state.counters["lines"] = live;
}
void BM_SteadyFrame(benchmark::State& state) { FrameAfterFirst(state, false); }
void BM_NewReferenceFrame(benchmark::State& state) { FrameAfterFirst(state, true); }
BENCHMARK(BM_SteadyFrame)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NewReferenceFrame)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace slt

BENCHMARK_MAIN();
