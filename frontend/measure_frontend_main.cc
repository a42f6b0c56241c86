// measure_frontend: the image front end against the ground truth of rendered sequences
// (issue 18's numbers; docs/frontend.md quotes the output in results/frontend/).
//
//   measure_frontend [--frames N] [--step K] [--method NAME] [--tracker-config FILE] [--config FILE] [--out DIR]
//                    [--scene TEXT] [--skip-detectors | --skip-sequences] [--first F] [--detector NAME] [--seed S]
//                    [--draws N]
//
// Four scenes are rendered in memory (render/, default image settings: noise, defocus blur,
// vignetting, exposure changes; --seed S: another draw of their scenes, motions and image noise,
// 1 by default, the draw results/frontend/ holds): the room loop at 752 x 480 (EuRoC's image size and focal
// length), the corridor walked forward at 640 x 480, the paper's scene and motion (Sec. 5.1)
// at 640 x 480 and the room loop on the default 640 x 480 rig (a narrower view), N frames
// each (--scene: those whose name contains TEXT). On the paper scene the "noisy" run below is the synthetic paper
// protocol at the front end's noise level.
//
// 1. detectors.md: every detector of frontend/line_detection.h, with --config's detection options
//    (snap_detections on the derivatives of the flow's pyramid, whose building is not timed) and the front end's merging,
//    length and contrast filters, on frames 0, K, 2K, ... of both (both cameras; --first F: F, F + K, ...,
//    the other frames, to tune on without tuning on the reported ones; --detector: that one only): recall = the
//    fraction of the visible ground-truth segments at least 40 px long that a detection lies on
//    (within 2 px and 2 deg, frontend_audit.h), precision = the fraction of detections that lie
//    on some ground-truth segment, the RMS perpendicular endpoint error of those, and the
//    single-thread time per image; and the recall of those ground-truth segments that are
//    photometrically visible (frontend_audit.h: the step across them in the same image rendered
//    without sensor noise at least the noise of a two-pixel difference). With --draws N > 1, the
//    front end's detector (--config's, EDLines by default) also on the same frames of draws
//    S + 1, ..., S + N - 1: its recall pooled over the draws, the worst and best draw's, and
//    each draw's.
// 2. sequences.md: the front end paired with the tracker over each whole sequence (the paper
//    scene with its own disparity range and match verification, PaperSceneOptions, and
//    --config's options over them): stereo matches and temporal tracks correct (same 3-D
//    segment; frontend_audit.h; within 2 px and 2 deg, and for identity alone within 3 px and
//    5 deg), endpoint error of the output lines, the tracker's ATE from the images against the
//    same tracker on the perfect observations of the sequence (the visible ground-truth edges,
//    noise-free) and on those observations with Gaussian endpoint noise at the front end's
//    measured RMS endpoint error, and on the front end's own tracks with their across-line
//    error replaced by none and by that Gaussian noise (WithErrorReplaced: same lines, ids and
//    frames as the run, so that the comparison separates the front end's precision from the
//    lines it supplies), and the per-stage times of steady and new-reference frames. Matches,
//    tracks and endpoint errors are judged against the scene's lines and, on the paper scene,
//    its bars' second edges (WithBarSecondEdges).
// 3. draws.md (--draws N > 1): the sequences' key numbers on draws S, S + 1, ..., S + N - 1 and,
//    per scene, their median, mean and largest ATE, the median and largest ratio of images to
//    the noisy run and how many draws are within the 1.5x, the worst draw's correct
//    matches and tracks, and the frames lost (one draw is one seed; a single one can mislead:
//    the paper scene's ATE swings over draws, docs/frontend.md).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "common/command_line.h"
#include "common/json_reader.h"
#include "common/table.h"
#include "dataset/trajectory.h"
#include "evaluation/metrics.h"
#include "evaluation/statistics.h"
#include "frontend/frontend_audit.h"
#include "frontend/image_tracking.h"
#include "frontend/parallel_edges.h"
#include "frontend/rendered_pair.h"
#include "render/sequence_renderer.h"

namespace slt {
namespace {

using Clock = std::chrono::steady_clock;

// A scene of the measurement, simulated once for both tables and rendered on demand.
struct MeasuredScene {
  MeasuredScene(std::string name, const nlohmann::json& config) : name(std::move(name)), rendered(config) {}
  std::string name;
  RenderedSequence rendered;
  // Its front-end options over the defaults (a JSON merge patch): the scene's own
  // (PaperSceneOptions) with --config's over them (what a user asks for explicitly wins); and
  // the options they make, checked when the scene is made, before any work.
  nlohmann::json options = nlohmann::json::object();
  FrontEndOptions front_end;
};

// A deque: each scene's renderer refers to its own sequence, which must not move.
std::deque<MeasuredScene> Scenes(int frames, const std::string& only_scene, std::uint64_t seed,
                                 const nlohmann::json& config_options) {
  std::vector<std::pair<std::string, nlohmann::json>> all = {
      {"room 752x480 (loop)", RenderedRoomConfig(frames, true)},
      {"corridor 640x480 (forward)", RenderedCorridorConfig(frames)},
      {"paper scene 640x480 (paper motion)", RenderedPaperConfig(frames)},
      {"room 640x480 (loop, default rig)", RenderedRoomConfig(frames, false)}};
  std::deque<MeasuredScene> scenes;
  for (auto& [name, json] : all) {
    if (name.find(only_scene) == std::string::npos) continue;
    json["seed"] = seed;
    scenes.emplace_back(name, json);
    if (name.rfind("paper", 0) == 0) scenes.back().options = PaperSceneOptions(scenes.back().rendered.rig());
    scenes.back().options.merge_patch(config_options);
    // Keys it does not hold keep their defaults.
    scenes.back().front_end =
        FrontEndOptionsFromJson(scenes.back().options, name + ", --config over its own options");
  }
  return scenes;
}

// A Markdown table with these column titles, the first `left` of them left-aligned.
Table MarkdownTable(const std::vector<std::string>& titles, size_t left) {
  Table table;
  for (size_t c = 0; c < titles.size(); ++c) table.columns.emplace_back(titles[c], c < left ? Table::Align::kLeft : Table::Align::kRight);
  return table;
}

// The images a detector is scored on in one scene: frames first, first + step, ... of both
// cameras, each with the ground truth photometrically visible in it.
struct ScoredImages {
  std::vector<cv::Mat> images;
  std::vector<std::pair<int, int>> which;  // frame, camera
  std::vector<std::vector<LineObservation>> photometric;
};

ScoredImages ImagesToScore(const MeasuredScene& scene, int first, int step) {
  const SimulationConfig& config = scene.rendered.config();
  const SimulatedSequence& sequence = scene.rendered.sequence();
  // The same images without sensor noise, for the photometric visibility of the ground truth.
  SimulationConfig noise_free = config;
  noise_free.images.read_noise = 0.0;
  noise_free.images.shot_noise = 0.0;
  const SequenceRenderer noise_free_renderer(sequence, noise_free);
  ScoredImages scored;
  for (int k = first; k < config.frames; k += step) {
    for (int c = 0; c < 2; ++c) {
      scored.images.push_back(scene.rendered.Image(k, c));
      scored.which.emplace_back(k, c);
      const StereoFrame& frame = sequence.sequence.frames[k];
      scored.photometric.push_back(
          PhotometricallyVisible(c == 0 ? frame.left : frame.right, noise_free_renderer.Image(k, c), config.images));
    }
  }
  return scored;
}

// One detector with `options` (and the front end's merging, length and contrast filters, snap
// and second edges) on the scored images: against the visible ground truth and against its
// photometrically visible part.
void ScoreDetector(const MeasuredScene& scene, const ScoredImages& scored, const DetectionOptions& options,
                   const TrackingOptions& tracking, DetectionScore* score, DetectionScore* photometric_score) {
  const SimulatedSequence& sequence = scene.rendered.sequence();
  const std::unique_ptr<LineDetector> detector = MakeLineDetector(options);
  const LineFlowTracker flow(tracking);
  ImagePyramid pyramid;
  SnapWorkspace snap;
  for (size_t i = 0; i < scored.images.size(); ++i) {
    const auto t0 = Clock::now();
    std::vector<ImageLine> lines = DetectLines(*detector, options, scored.images[i]);
    if (options.snap_detections) {
      // As the front end does (the derivatives of the flow pyramid, built there anyway, are
      // not timed here).
      const auto t1 = Clock::now();
      flow.BuildPyramid(scored.images[i], &pyramid, 0);
      score->seconds -= std::chrono::duration<double>(Clock::now() - t1).count();
      SnapDetections(tracking, options.min_length_px, pyramid[1], &lines, &snap);
    }
    AddParallelEdges(options, tracking.snap_min_gradient, scored.images[i], &lines);
    score->seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    const auto [k, c] = scored.which[i];
    const StereoFrame& frame = sequence.sequence.frames[k];
    const ProjectedGroundTruth projected = ProjectedGroundTruthAt(sequence, k, c);
    ScoreDetections(projected, c == 0 ? frame.left : frame.right, lines, 40.0, score);
    ScoreDetections(projected, scored.photometric[i], lines, 40.0, photometric_score);
  }
}

// The detector of --config's options (EDLines by default) on one scene of one draw.
struct DrawDetection {
  std::string scene;
  DetectionScore score, photometric;
};

// The detector table; the front end's own detector's scores per scene also into
// `front_end_detector` (empty when --detector left it out).
std::string DetectorTable(const std::deque<MeasuredScene>& scenes, int first, int step, const std::string& only_detector,
                          const FrontEndOptions& front_end_options, std::vector<DrawDetection>* front_end_detector) {
  Table table = MarkdownTable({"scene", "detector", "images", "GT segments >= 40 px", "recall", "precision",
                               "endpoint RMS, px", "segments per image", "ms per image",
                               "of those, photometrically visible", "recall of those"},
                              2);
  for (const MeasuredScene& scene : scenes) {
    const ScoredImages scored = ImagesToScore(scene, first, step);
    for (const auto& [type, name] : LineDetectorNames()) {
      if (!only_detector.empty() && only_detector != name) continue;
      DetectionOptions options = front_end_options.detection;  // --config's detection options, each detector in turn
      options.detector = type;
      DetectionScore score, photometric_score;
      ScoreDetector(scene, scored, options, front_end_options.tracking, &score, &photometric_score);
      table.AddRow({scene.name, name, std::to_string(score.images), std::to_string(score.gt_segments),
                    StringPrintf("%.3f", score.Recall()), StringPrintf("%.3f", score.Precision()),
                    StringPrintf("%.2f", score.EndpointRms()),
                    StringPrintf("%.0f", static_cast<double>(score.detections) / score.images),
                    StringPrintf("%.1f", 1e3 * score.seconds / score.images),
                    std::to_string(photometric_score.gt_segments), StringPrintf("%.3f", photometric_score.Recall())});
      std::fprintf(stderr, "measure_frontend: %s, %s: recall %.3f\n", scene.name.c_str(), name, score.Recall());
      if (type == front_end_options.detection.detector) front_end_detector->push_back({scene.name, score, photometric_score});
    }
  }
  return table.Markdown();
}

DrawDetection ScoreDefaultDetector(const MeasuredScene& scene, int first, int step, const FrontEndOptions& options) {
  DrawDetection d{scene.name, {}, {}};
  ScoreDetector(scene, ImagesToScore(scene, first, step), options.detection, options.tracking, &d.score, &d.photometric);
  return d;
}

// The draw table of detectors.md (--draws N > 1): `draws[d][i]` measured on scene i of draw
// `first_seed + d`; per scene the recall pooled over the draws, the worst and best draw's, then
// each draw's row.
std::string DrawDetectorTable(std::uint64_t first_seed, const std::string& detector,
                              const std::vector<std::vector<DrawDetection>>& draws) {
  Table summary = MarkdownTable({"scene", "detector", "draws", "GT segments >= 40 px", "recall", "worst draw",
                                 "best draw", "of those, photometrically visible", "recall of those"},
                                2);
  Table table = MarkdownTable({"scene", "draw (--seed)", "GT segments >= 40 px", "found", "recall",
                               "of those, photometrically visible", "recall of those"},
                              1);
  for (size_t i = 0; i < draws[0].size(); ++i) {
    DetectionScore pooled, pooled_photometric;
    double worst = 1.0, best = 0.0;
    for (size_t d = 0; d < draws.size(); ++d) {
      const DrawDetection& m = draws[d][i];
      table.AddRow({m.scene, std::to_string(first_seed + d), std::to_string(m.score.gt_segments),
                    std::to_string(m.score.gt_found), StringPrintf("%.3f", m.score.Recall()), std::to_string(m.photometric.gt_segments),
                    StringPrintf("%.3f", m.photometric.Recall())});
      pooled.gt_segments += m.score.gt_segments;
      pooled.gt_found += m.score.gt_found;
      pooled_photometric.gt_segments += m.photometric.gt_segments;
      pooled_photometric.gt_found += m.photometric.gt_found;
      worst = std::min(worst, m.score.Recall());
      best = std::max(best, m.score.Recall());
    }
    summary.AddRow({draws[0][i].scene, detector, std::to_string(draws.size()), std::to_string(pooled.gt_segments),
                    StringPrintf("%.3f", pooled.Recall()), StringPrintf("%.3f", worst), StringPrintf("%.3f", best),
                    std::to_string(pooled_photometric.gt_segments), StringPrintf("%.3f", pooled_photometric.Recall())});
  }
  return summary.Markdown() + "\nEach draw:\n\n" + table.Markdown();
}

double Ate(const SimulatedSequence& sequence, const Trajectory& estimate) {
  return EvaluateTrajectory(sequence.ground_truth, estimate, EvaluationOptions()).ate_trans_m.rmse;
}

// The tracker paired with the front end (--method, --tracker-config).
struct TrackerChoice {
  std::string method;
  nlohmann::json options;
  std::string where;  // the options' file, for errors
  std::unique_ptr<PoseTracker> Create() const { return CreateTracker(method, options, where); }
};

Trajectory TrackObservations(const TrackerChoice& choice, const StereoSequence& observations) {
  const std::unique_ptr<PoseTracker> tracker = choice.Create();
  Trajectory trajectory;
  for (const TrackedFrame& frame : TrackSequence(*tracker, observations)) {
    trajectory.push_back({frame.frame_time, frame.output.cam_from_world.Inverse()});
  }
  return trajectory;
}

// One scene's measurement, the numbers of sequences.md's and draws.md's rows.
struct SequenceResult {
  std::string scene;
  int frames = 0;
  double path_m = 0.0;
  FrontEndAudit::Result audit, identity;  // within 2 px and 2 deg; identity alone (3 px, 5 deg)
  // ATE (m) from the images, the perfect and the noisy observations, the front end's own tracks
  // on the truth and with noise of its RMS.
  double ate_images = 0.0, ate_perfect = 0.0, ate_noisy = 0.0, ate_own_truth = 0.0, ate_own_noisy = 0.0;
  FrontEndStageTimes steady, detecting;
  int steady_frames = 0, detection_frames = 0, new_references = 0, lost = 0;
  long described = 0;  // lines described on the detection frames
  double tracker_seconds = 0.0;
  // The ATE from the images over that of the noisy observations and of its own noisy tracks.
  double RatioToNoisy() const { return ate_images / ate_noisy; }
  double RatioToOwnNoisy() const { return ate_images / ate_own_noisy; }
};

SequenceResult MeasureSequence(const MeasuredScene& scene, const TrackerChoice& choice) {
  const SimulationConfig& config = scene.rendered.config();
  const SimulatedSequence& sequence = scene.rendered.sequence();
  SequenceResult result;
  result.scene = scene.name;
  result.frames = config.frames;
  result.path_m = PathLengthM(sequence.ground_truth);
  const std::unique_ptr<PoseTracker> tracker = choice.Create();
  StereoFrontEnd front_end(scene.front_end, sequence.true_rig);
  ImageTracker image_tracker(front_end, *tracker, sequence.true_rig);
  // Judged against the scene's lines and, on the paper scene, its bars' second edges.
  SimulatedSequence judged = sequence;
  judged.lines = WithBarSecondEdges(sequence);
  FrontEndAudit audit(judged);
  // Identity only (the same 3-D segment, however precisely): looser than detection's 2 px and
  // 2 deg, which a short segment with sub-pixel endpoint errors can exceed in angle.
  FrontEndAudit identity(judged, AuditCriteria{3.0, 5.0});
  StereoSequence observed;  // the front end's output, for the error-model runs below
  observed.rig = sequence.true_rig;
  Trajectory from_images;
  for (int k = 0; k < config.frames; ++k) {
    const cv::Mat left = scene.rendered.Image(k, 0), right = scene.rendered.Image(k, 1);
    const double time = sequence.sequence.frames[k].time;
    const ImageTrackingStep step = image_tracker.Step(left, right, time);
    audit.AddFrame(k, front_end, *step.frame);
    identity.AddFrame(k, front_end, *step.frame);
    observed.frames.push_back(*step.frame);
    const FrontEndFrameStats& stats = front_end.last_stats();
    if (stats.detected) {
      result.detecting += stats.times;
      ++result.detection_frames;
      result.described += stats.detected_left + stats.detected_right;
    } else {
      result.steady += stats.times;
      ++result.steady_frames;
    }
    result.tracker_seconds += step.tracker_seconds;
    if (k > 0 && step.output.status == TrackingStatus::kNewReference) ++result.new_references;
    if (step.output.status == TrackingStatus::kLost) ++result.lost;
    from_images.push_back({time, step.output.cam_from_world.Inverse()});
  }
  audit.Finish();
  identity.Finish();
  result.audit = audit.result();
  result.identity = identity.result();
  const double rms = result.audit.EndpointRms();
  result.ate_images = Ate(sequence, from_images);
  result.ate_perfect = Ate(sequence, TrackObservations(choice, sequence.sequence));
  // The same observations with Gaussian endpoint noise of the front end's RMS error (the
  // noise stream differs from the scene's and the motion's: same lines, same poses).
  SimulationConfig noisy_config = config;
  noisy_config.noise.model = NoiseModel::kGaussian;
  noisy_config.noise.endpoint_px = rms;
  result.ate_noisy = Ate(sequence, TrackObservations(choice, Simulate(noisy_config).sequence));
  // The front end's own tracks (same lines, ids and frames) with its across-line error replaced:
  // by none, and by independent Gaussian noise of its RMS (the synthetic protocol's model).
  const std::uint64_t seed = config.NoiseSeed();
  result.ate_own_truth =
      Ate(sequence, TrackObservations(choice, WithErrorReplaced(sequence, judged.lines, observed, 0.0, seed)));
  result.ate_own_noisy =
      Ate(sequence, TrackObservations(choice, WithErrorReplaced(sequence, judged.lines, observed, rms, seed)));
  std::fprintf(stderr,
               "measure_frontend: %s: ATE images %.2f mm, perfect %.2f mm, noisy %.2f mm, its tracks on the truth "
               "%.2f mm, + noise %.2f mm\n",
               scene.name.c_str(), 1e3 * result.ate_images, 1e3 * result.ate_perfect, 1e3 * result.ate_noisy,
               1e3 * result.ate_own_truth, 1e3 * result.ate_own_noisy);
  return result;
}

std::string Formatted(const char* format, double v) { return StringPrintf(format, v); }

// sequences.md: `results[i]` measured on `scenes[i]`.
std::string SequenceTable(const std::deque<MeasuredScene>& scenes, const std::vector<SequenceResult>& results) {
  Table table = MarkdownTable(
      {"scene", "frames", "path, m", "detection frames", "new references", "lost", "stereo matches", "not judged",
       "correct (of judged)", "correct, 3 px 5 deg", "tracks (>= 2 frames, judged)", "not judged", "correct",
       "correct, 3 px 5 deg", "mean track length", "endpoint RMS, px", "ATE images, mm", "ATE perfect, mm",
       "ATE noisy (same RMS), mm", "ratio images / perfect", "ratio images / noisy",
       "ATE its tracks on the truth, mm", "ATE its tracks + noise (same RMS), mm", "ratio images / its tracks noisy"},
      1);
  Table times = MarkdownTable({"scene", "steady frames", "track, ms", "filter, ms", "steady front end, ms",
                               "new-reference frames", "detect, ms", "describe, ms", "match, ms", "track, ms",
                               "filter, ms", "new-reference front end, ms", "MSLD per line, us",
                               "lines described per frame", "tracker, ms"},
                              1);
  const auto f = Formatted;
  const auto n = [](long v) { return std::to_string(v); };
  for (const SequenceResult& m : results) {
    const FrontEndAudit::Result& r = m.audit;
    const FrontEndAudit::Result& ri = m.identity;
    table.AddRow({m.scene, n(m.frames), f("%.2f", m.path_m), n(m.detection_frames), n(m.new_references), n(m.lost),
                  n(r.matches), n(r.matches_unjudged), f("%.4f", r.MatchPrecision()), f("%.4f", ri.MatchPrecision()),
                  n(r.tracks), n(r.tracks_unjudged), f("%.4f", r.TrackPrecision()), f("%.4f", ri.TrackPrecision()),
                  f("%.1f", r.tracks ? static_cast<double>(r.track_frames) / r.tracks : 0.0),
                  f("%.3f", r.EndpointRms()), f("%.2f", 1e3 * m.ate_images), f("%.2f", 1e3 * m.ate_perfect),
                  f("%.2f", 1e3 * m.ate_noisy), f("%.2f", m.ate_images / m.ate_perfect),
                  f("%.2f", m.RatioToNoisy()), f("%.2f", 1e3 * m.ate_own_truth),
                  f("%.2f", 1e3 * m.ate_own_noisy), f("%.2f", m.RatioToOwnNoisy())});
    const auto ms = [&](double s, int count) { return f("%.2f", count ? 1e3 * s / count : 0.0); };
    const FrontEndStageTimes& steady = m.steady;
    const FrontEndStageTimes& detecting = m.detecting;
    const int steady_frames = m.steady_frames, detection_frames = m.detection_frames;
    times.AddRow({m.scene, n(steady_frames), ms(steady.track, steady_frames), ms(steady.filter, steady_frames),
                  ms(steady.Total(), steady_frames), n(detection_frames), ms(detecting.detect, detection_frames),
                  ms(detecting.describe, detection_frames), ms(detecting.match, detection_frames),
                  ms(detecting.track, detection_frames), ms(detecting.filter, detection_frames),
                  ms(detecting.Total(), detection_frames),
                  f("%.1f", m.described ? 1e6 * detecting.describe / m.described : 0.0),
                  f("%.0f", detection_frames ? static_cast<double>(m.described) / detection_frames : 0.0),
                  ms(m.tracker_seconds, m.frames)});
  }
  std::string notes;
  for (const MeasuredScene& scene : scenes) {
    if (!scene.options.empty()) notes += "\nFront-end options of " + scene.name + ": `" + scene.options.dump() + "`.\n";
  }
  return table.Markdown() + notes + "\nPer-stage times (wall clock inside the run, single thread):\n\n" + times.Markdown();
}

// The bound on the ATE from the images against the noisy run (issue 18).
constexpr double kRatioBound = 1.5;

// draws.md: `draws[d][i]` measured on scene i of draw `first_seed + d`; per draw its row, then
// per scene the statistics over the draws.
std::string DrawTable(std::uint64_t first_seed, const std::vector<std::vector<SequenceResult>>& draws) {
  Table table = MarkdownTable({"scene", "draw (--seed)", "new references", "lost", "stereo matches", "correct",
                               "tracks", "correct", "endpoint RMS, px", "ATE images, mm", "ATE noisy (same RMS), mm",
                               "ratio images / noisy", "ratio images / its tracks noisy"},
                              1);
  Table summary = MarkdownTable({"scene", "draws", "ATE images median, mm", "mean, mm", "max, mm",
                                 "ratio images / noisy median", "max", StringPrintf("draws with ratio <= %g", kRatioBound),
                                 "ratio images / its tracks noisy median", "stereo matches correct, worst draw",
                                 "tracks correct, worst draw", "frames lost"},
                                1);
  const auto f = Formatted;
  for (size_t i = 0; i < draws[0].size(); ++i) {
    std::vector<double> ate, ratio, own_ratio;
    double worst_matches = 1.0, worst_tracks = 1.0;
    int lost = 0, within = 0;
    for (size_t d = 0; d < draws.size(); ++d) {
      const SequenceResult& m = draws[d][i];
      table.AddRow({m.scene, std::to_string(first_seed + d), std::to_string(m.new_references), std::to_string(m.lost),
                    std::to_string(m.audit.matches), f("%.4f", m.audit.MatchPrecision()),
                    std::to_string(m.audit.tracks), f("%.4f", m.audit.TrackPrecision()),
                    f("%.3f", m.audit.EndpointRms()), f("%.2f", 1e3 * m.ate_images), f("%.2f", 1e3 * m.ate_noisy),
                    f("%.2f", m.RatioToNoisy()), f("%.2f", m.RatioToOwnNoisy())});
      ate.push_back(m.ate_images);
      ratio.push_back(m.RatioToNoisy());
      own_ratio.push_back(m.RatioToOwnNoisy());
      worst_matches = std::min(worst_matches, m.audit.MatchPrecision());
      worst_tracks = std::min(worst_tracks, m.audit.TrackPrecision());
      lost += m.lost;
      within += ratio.back() <= kRatioBound;
    }
    const ErrorStatistics a = ComputeStatistics(ate), q = ComputeStatistics(ratio);
    summary.AddRow({draws[0][i].scene, std::to_string(draws.size()), f("%.2f", 1e3 * a.median),
                    f("%.2f", 1e3 * a.mean), f("%.2f", 1e3 * a.max), f("%.2f", q.median), f("%.2f", q.max),
                    std::to_string(within), f("%.2f", ComputeStatistics(own_ratio).median),
                    f("%.4f", worst_matches), f("%.4f", worst_tracks), std::to_string(lost)});
  }
  return summary.Markdown() + "\nEach draw:\n\n" + table.Markdown();
}

}  // namespace
}  // namespace slt

int main(int argc, char** argv) {
  using namespace slt;
  CLI::App app{"Measure the image front end on rendered sequences (results/frontend/)."};
  int frames = 200, step = 20;
  std::string method = "trifocal_line_ekf", tracker_config_path, out, config_path;
  bool skip_detectors = false, skip_sequences = false;
  std::string only_scene, only_detector;
  int first = 0, draws = 1;
  std::uint64_t seed = 1;
  std::string seed_text;
  app.add_option("--frames", frames, "Frames per sequence")->check(CLI::Range(2, 100000));
  app.add_option("--step", step, "Detector table: every step-th frame")->check(CLI::Range(1, 100000));
  app.add_option("--out", out, "Write detectors.md, sequences.md and (--draws > 1) draws.md into this folder");
  AddTrackerOptions(app, &method, &tracker_config_path, "--tracker-config");
  app.add_option("--config", config_path,
                 "Front-end options, JSON (docs/frontend.md), over each scene's own (the paper scene's)");
  app.add_flag("--skip-detectors", skip_detectors, "Only the sequences");
  app.add_flag("--skip-sequences", skip_sequences, "Only the detectors");
  app.add_option("--scene", only_scene, "Only the scenes whose name contains this (room, corridor, paper)");
  app.add_option("--first", first, "Detector table: the first frame scored (then every --step)")->check(CLI::NonNegativeNumber);
  // Read as text (ParseSeedOption).
  app.add_option("--seed", seed_text, "Simulation seed of every scene (another draw of the scenes, motions and image noise)");
  app.add_option("--detector", only_detector, "Detector table: only this detector (lsd, edlines, ...)");
  app.add_option("--draws", draws,
                 "Also draws --seed + 1, ..., --seed + N - 1: each draw's numbers and their statistics in draws.md "
                 "and, for the front end's detector, in detectors.md (sequences.md and the detector table: the first "
                 "draw)")
      ->check(CLI::Range(1, 100000));
  const int exit_code = ParseCommandLine(app, argc, argv, "measure_frontend", [&] {
    if (app.count("--seed") > 0) seed = ParseSeedOption("--seed", seed_text);
  });
  if (exit_code >= 0) return exit_code;
  return RunProgram("measure_frontend", [&] {
    cv::setNumThreads(1);
    const nlohmann::json config_options = ReadOptionsFile(config_path);
    const FrontEndOptions options = FrontEndOptionsFromJson(config_options, config_path);
    const TrackerChoice choice{method, ReadOptionsFile(tracker_config_path), tracker_config_path};
    choice.Create();  // an unknown tracker or invalid options fail before the work
    const std::deque<MeasuredScene> scenes = Scenes(frames, only_scene, seed, config_options);
    // The options measured, when not the defaults: the configs' file names, then their contents.
    const auto config_note = [&](bool with_tracker) {
      std::string flags, contents;
      for (const auto& [flag, path] :
           {std::pair{"--tracker-config", with_tracker ? tracker_config_path : ""}, {"--config", config_path}}) {
        if (path.empty()) continue;
        flags += std::string(" ") + flag + " " + std::filesystem::path(path).filename().string();
        contents += (contents.empty() ? "` with `" : "`, `") + ReadJsonFile(path).dump();
      }
      return flags + contents;
    };
    // Each file's header names the options its numbers depend on: the detector tables not on the
    // tracker, the sequences not on --step, --first or --detector (sequences.md not on --draws).
    const std::string seed_flag = seed != 1 ? " --seed " + std::to_string(seed) : std::string();
    const std::string detector_header =
        StringPrintf("Generated by `measure_frontend --frames %d --step %d%s%s%s%s%s`.\n\n", frames, step,
                     first ? StringPrintf(" --first %d", first).c_str() : "", seed_flag.c_str(),
                     draws > 1 ? StringPrintf(" --draws %d", draws).c_str() : "",
                     only_detector.empty() ? "" : (" --detector " + only_detector).c_str(),
                     config_note(false).c_str());
    const auto sequence_header = [&](bool with_draws) {
      return StringPrintf("Generated by `measure_frontend --frames %d --method %s%s%s%s`.\n\n", frames,
                          method.c_str(), seed_flag.c_str(), with_draws ? StringPrintf(" --draws %d", draws).c_str() : "",
                          config_note(true).c_str());
    };
    std::vector<std::vector<SequenceResult>> results(draws);
    std::vector<std::vector<DrawDetection>> detections(draws);
    std::string detectors =
        skip_detectors ? "" : detector_header + DetectorTable(scenes, first, step, only_detector, options, &detections[0]);
    const bool detection_draws = !skip_detectors && draws > 1;
    // The first draw's scores are the detector table's, unless --detector left the front end's out.
    const bool score_first_draw = detections[0].empty();
    for (int d = 0; d < draws && (!skip_sequences || detection_draws); ++d) {
      // Each draw's scenes are simulated (and rendered) only while it is measured.
      const std::deque<MeasuredScene> drawn =
          d == 0 ? std::deque<MeasuredScene>() : Scenes(frames, only_scene, seed + d, config_options);
      for (const MeasuredScene& scene : d == 0 ? scenes : drawn) {
        if (detection_draws && (d > 0 || score_first_draw)) {
          detections[d].push_back(ScoreDefaultDetector(scene, first, step, options));
        }
        if (!skip_sequences) results[d].push_back(MeasureSequence(scene, choice));
      }
    }
    if (detection_draws) {
      const std::string detector = EnumName(LineDetectorNames(), options.detection.detector);
      detectors += StringPrintf("\nThe front end's detector (%s) on draws %llu to %llu, the same frames of each:\n\n",
                                detector.c_str(), static_cast<unsigned long long>(seed),
                                static_cast<unsigned long long>(seed + draws - 1)) +
                   DrawDetectorTable(seed, detector, detections);
    }
    std::string sequences, draw_table;
    if (!skip_sequences) {
      sequences = sequence_header(false) + SequenceTable(scenes, results[0]);
      if (draws > 1) draw_table = sequence_header(true) + DrawTable(seed, results);
    }
    std::printf("%s\n%s\n%s", detectors.c_str(), sequences.c_str(), draw_table.c_str());
    if (!out.empty()) {
      // Every output or none: all are made before the first is written (each atomically).
      std::filesystem::create_directories(out);
      if (!skip_detectors) WriteTextFileAtomically(out + "/detectors.md", detectors);
      if (!skip_sequences) WriteTextFileAtomically(out + "/sequences.md", sequences);
      if (!skip_sequences && draws > 1) WriteTextFileAtomically(out + "/draws.md", draw_table);
    }
    return 0;
  });
}
