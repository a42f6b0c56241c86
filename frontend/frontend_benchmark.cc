// Per-stage speed of the image front end (issue 18: a steady frame <= 5 ms, a new-reference
// frame <= 30 ms for a 752 x 480 stereo pair, MSLD <= 20 us per 50-px line), single thread, on
// frames 0 to 2 of the rendered room loop at 752 x 480 (frontend_audit.h). docs/frontend.md
// quotes the numbers.
//
//   frontend_benchmark [--config=frontend.json] [--benchmark_repetitions=3]
//
// --config (docs/frontend.md's options) replaces the default options in the frame benchmarks
// and the detection options of BM_DetectOneImage.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "common/json_reader.h"

#include "frontend/frontend_audit.h"
#include "frontend/stereo_frontend.h"
#include "render/sequence_renderer.h"
#include "simulator/simulation_config.h"

namespace slt {
namespace {

constexpr int kFrames = 3;

struct Pairs {
  StereoRig rig;
  cv::Mat images[kFrames][2];  // [frame][camera]
};

FrontEndOptions& BenchmarkOptions() {
  static FrontEndOptions options;
  return options;
}

const Pairs& RenderedPairs() {
  static const Pairs pairs = [] {
    cv::setNumThreads(1);
    const SimulationConfig config = SimulationConfigFromJson(RenderedRoomConfig(200, true), "frontend_benchmark");
    const SimulatedSequence sequence = Simulate(config);
    const SequenceRenderer renderer(sequence, config);
    Pairs p;
    p.rig = sequence.true_rig;
    for (int k = 0; k < kFrames; ++k) {
      for (int c = 0; c < 2; ++c) p.images[k][c] = renderer.Image(k, c);
    }
    return p;
  }();
  return pairs;
}

void BM_DetectOneImage(benchmark::State& state) {
  const LineDetectorType type = static_cast<LineDetectorType>(state.range(0));
  DetectionOptions options = BenchmarkOptions().detection;  // --config's, each detector in turn
  options.detector = type;
  const std::unique_ptr<LineDetector> detector = MakeLineDetector(options);
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
  const std::unique_ptr<LineDetector> detector = MakeLineDetector(DetectionOptions());
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

// The steady frame's parts in one image (left, frame 0 to 1; the lines detected in frame 0):
// the pyramid of one image, the flow of the lines' points, and the refit.
void BM_TrackPyramidOneImage(benchmark::State& state) {
  LineFlowTracker tracker(BenchmarkOptions().tracking);
  ImagePyramid pyramid;
  for (auto _ : state) {
    tracker.BuildPyramid(RenderedPairs().images[1][0], &pyramid);
    benchmark::DoNotOptimize(pyramid.data());
  }
}
BENCHMARK(BM_TrackPyramidOneImage)->Unit(benchmark::kMillisecond);

std::vector<Segment2d> FirstLeftLines() {
  const std::unique_ptr<LineDetector> detector = MakeLineDetector(BenchmarkOptions().detection);
  std::vector<Segment2d> segments;
  for (const ImageLine& line : DetectLines(*detector, BenchmarkOptions().detection, RenderedPairs().images[0][0])) {
    segments.push_back(line.segment);
  }
  return segments;
}

// A tracker with the pyramids of frames 0 and 1 (left) and the lines of frame 0.
struct FlowSetup {
  LineFlowTracker tracker{BenchmarkOptions().tracking};
  ImagePyramid previous, next;
  std::vector<Segment2d> segments = FirstLeftLines();
  FlowSetup() {
    tracker.BuildPyramid(RenderedPairs().images[0][0], &previous);
    tracker.BuildPyramid(RenderedPairs().images[1][0], &next);
  }
};

void BM_TrackFlowOneImage(benchmark::State& state) {
  FlowSetup setup;
  for (auto _ : state) setup.tracker.Flow(setup.previous, setup.next, setup.segments);
  state.counters["lines"] = static_cast<double>(setup.segments.size());
}
BENCHMARK(BM_TrackFlowOneImage)->Unit(benchmark::kMillisecond);

void BM_TrackRefitOneImage(benchmark::State& state) {
  FlowSetup setup;
  setup.tracker.Flow(setup.previous, setup.next, setup.segments);
  std::vector<Segment2d> tracked;
  std::vector<LineLoss> losses;
  for (auto _ : state) setup.tracker.Refit(setup.next[0].cols, setup.next[0].rows, &tracked, &losses);
  state.counters["kept"] = static_cast<double>(std::count(losses.begin(), losses.end(), LineLoss::kKept));
}
BENCHMARK(BM_TrackRefitOneImage)->Unit(benchmark::kMillisecond);

// Frame 2 after frames 0 (detected) and 1 (tracked), so that the pyramids' buffers are reused
// as in a running front end: with detection (a new-reference frame: track + filter + detect
// both images + MSLD + match) or without (a steady frame: track + filter). The counters give
// the per-stage CPU-bound wall time of the timed frame (FrontEndStageTimes), in ms.
void FrameAfterFirst(benchmark::State& state, bool detect) {
  const Pairs& pairs = RenderedPairs();
  const FrontEndOptions& options = BenchmarkOptions();
  int live = 0;
  FrontEndStageTimes times;
  for (auto _ : state) {
    state.PauseTiming();
    StereoFrontEnd front_end(options, pairs.rig);
    front_end.Process(pairs.images[0][0], pairs.images[0][1], 0.0, true);
    front_end.Process(pairs.images[1][0], pairs.images[1][1], 1.0, false);
    state.ResumeTiming();
    const StereoFrame& frame = front_end.Process(pairs.images[2][0], pairs.images[2][1], 2.0, detect);
    live = static_cast<int>(frame.left.size());
    times += front_end.last_stats().times;
  }
  state.counters["lines"] = live;
  const double per_ms = 1e3 / static_cast<double>(state.iterations());
  state.counters["track_ms"] = times.track * per_ms;
  state.counters["filter_ms"] = times.filter * per_ms;
  if (detect) {
    state.counters["detect_ms"] = times.detect * per_ms;
    state.counters["describe_ms"] = times.describe * per_ms;
    state.counters["match_ms"] = times.match * per_ms;
  }
}
void BM_SteadyFrame(benchmark::State& state) { FrameAfterFirst(state, false); }
void BM_NewReferenceFrame(benchmark::State& state) { FrameAfterFirst(state, true); }
BENCHMARK(BM_SteadyFrame)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NewReferenceFrame)->Unit(benchmark::kMillisecond);

// The first pair of a run (no live line: every detection is described and matched; nothing is
// tracked): the new-reference frame's detection stages at their most work.
void BM_FirstFrame(benchmark::State& state) {
  const Pairs& pairs = RenderedPairs();
  const FrontEndOptions& options = BenchmarkOptions();
  FrontEndStageTimes times;
  int live = 0;
  for (auto _ : state) {
    state.PauseTiming();
    StereoFrontEnd front_end(options, pairs.rig);
    state.ResumeTiming();
    live = static_cast<int>(front_end.Process(pairs.images[0][0], pairs.images[0][1], 0.0, true).left.size());
    times += front_end.last_stats().times;
  }
  state.counters["lines"] = live;
  const double per_ms = 1e3 / static_cast<double>(state.iterations());
  state.counters["pyramids_ms"] = times.track * per_ms;
  state.counters["detect_ms"] = times.detect * per_ms;
  state.counters["describe_ms"] = times.describe * per_ms;
  state.counters["match_ms"] = times.match * per_ms;
}
BENCHMARK(BM_FirstFrame)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace slt

int main(int argc, char** argv) {
  // --config=FILE is ours; the rest goes to Google Benchmark.
  const std::string flag = "--config=";
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind(flag, 0) != 0) {
      args.push_back(argv[i]);
      continue;
    }
    const std::string path = arg.substr(flag.size());
    try {
      slt::BenchmarkOptions() = slt::FrontEndOptionsFromJson(slt::ReadJsonFile(path), path);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "frontend_benchmark: error: %s\n", e.what());
      return 1;
    }
  }
  int count = static_cast<int>(args.size());
  benchmark::Initialize(&count, args.data());
  if (benchmark::ReportUnrecognizedArguments(count, args.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
