// measure_lsd: how much of the ground truth a standard line detector finds in the rendered
// images. Renders the room, the corridor and the paper scene (frames 0, step, 2 step, ... of
// each sequence, both cameras, default image settings) and runs OpenCV's LSD at its default
// settings (cv::createLineSegmentDetector()). A visible ground-truth segment (the noise-free
// observations of the simulator with occlusion and clipping on, at least 20 px long) counts as
// found when a detected segment lies along it: direction within 3 deg, both detected endpoints
// within 2 px of the ground-truth line, and overlapping the ground-truth segment. Also
// reported: the fraction of the ground-truth length covered by such detections.
//
//   measure_lsd [--frames N] [--step K] [--out FILE.md]
//
// docs/rendering.md quotes its output (results/render/lsd_recall.md).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "common/command_line.h"
#include "common/json_reader.h"
#include "common/table.h"
#include "render/sequence_renderer.h"

namespace slt {
namespace {

constexpr double kMaxDistancePx = 2.0;
constexpr double kMaxAngleDeg = 3.0;
constexpr double kMinLengthPx = 20.0;

struct Recall {
  int segments = 0;
  int found = 0;
  double length = 0.0;
  double covered = 0.0;
  int detections = 0;
  int images = 0;
};

// Matches the detections against one image's ground truth.
void Score(const std::vector<LineObservation>& truth, const std::vector<cv::Vec4f>& detected, Recall* recall) {
  recall->detections += static_cast<int>(detected.size());
  ++recall->images;
  for (const LineObservation& o : truth) {
    const Eigen::Vector2d a = o.segment.head<2>(), b = o.segment.tail<2>();
    const double length = (b - a).norm();
    if (length < kMinLengthPx) continue;
    const Eigen::Vector2d d = (b - a) / length, n(-d.y(), d.x());
    // Covered part of [0, length], as a list of intervals merged at the end.
    std::vector<std::pair<double, double>> cover;
    for (const cv::Vec4f& s : detected) {
      const Eigen::Vector2d p(s[0], s[1]), q(s[2], s[3]);
      const Eigen::Vector2d e = (q - p).normalized();
      if (std::abs(e.dot(n)) > std::sin(kMaxAngleDeg * M_PI / 180.0)) continue;
      if (std::abs(n.dot(p - a)) > kMaxDistancePx || std::abs(n.dot(q - a)) > kMaxDistancePx) continue;
      double t0 = d.dot(p - a), t1 = d.dot(q - a);
      if (t0 > t1) std::swap(t0, t1);
      t0 = std::max(t0, 0.0);
      t1 = std::min(t1, length);
      if (t0 < t1) cover.emplace_back(t0, t1);
    }
    ++recall->segments;
    recall->length += length;
    if (cover.empty()) continue;
    ++recall->found;
    std::sort(cover.begin(), cover.end());
    double end = 0.0;
    for (const auto& [t0, t1] : cover) {
      if (t1 > end) recall->covered += t1 - std::max(t0, end);
      end = std::max(end, t1);
    }
  }
}

}  // namespace
}  // namespace slt

int main(int argc, char** argv) {
  using namespace slt;
  CLI::App app{"Fraction of the visible ground-truth segments found by OpenCV's LSD in rendered images."};
  int frames = 60, step = 10;
  std::string out;
  AddMeasurementOptions(app, &frames, 1, &step, &out, "Also write the table to this Markdown file");
  if (const int exit_code = ParseCommandLine(app, argc, argv, "measure_lsd"); exit_code >= 0) return exit_code;
  return RunProgram("measure_lsd", [&] {
    cv::setNumThreads(1);
    const cv::Ptr<cv::LineSegmentDetector> lsd = cv::createLineSegmentDetector();
    Table table;
    table.columns = {{"scene", Table::Align::kLeft}, {"images"}, {"visible segments (>= 20 px)"}, {"found"},
                     {"fraction found"}, {"length covered"}, {"LSD segments per image"}};
    for (const char* scene : {"room", "corridor", "paper"}) {
      // The ground truth is what the camera sees: clipped to the image, occluded parts removed.
      const nlohmann::json j = {{"scene", {{"type", scene}}},
                                {"frames", frames},
                                {"noise", {{"endpoint_px", 0.0}}},
                                {"observation", {{"clip_to_image", true}, {"occlusion", true}}}};
      const SimulationConfig config = SimulationConfigFromJson(j, "measure_lsd");
      const SimulatedSequence sequence = Simulate(config);
      const SequenceRenderer renderer(sequence, config);
      Recall recall;
      for (int k = 0; k < frames; k += step) {
        for (int camera = 0; camera < 2; ++camera) {
          cv::Mat image = renderer.Image(k, camera);
          std::vector<cv::Vec4f> detected;
          lsd->detect(image, detected);
          const StereoFrame& frame = sequence.sequence.frames[k];
          Score(camera == 0 ? frame.left : frame.right, detected, &recall);
        }
      }
      table.AddRow({scene, std::to_string(recall.images), std::to_string(recall.segments), std::to_string(recall.found),
                    StringPrintf("%.3f", static_cast<double>(recall.found) / std::max(1, recall.segments)),
                    StringPrintf("%.3f", recall.covered / std::max(1e-9, recall.length)),
                    StringPrintf("%.0f", static_cast<double>(recall.detections) / std::max(1, recall.images))});
      std::fprintf(stderr, "measure_lsd: %s done\n", scene);
    }
    std::printf("%s", table.Markdown().c_str());
    if (!out.empty()) WriteTextFileAtomically(out, table.Markdown());
    return 0;
  });
}
