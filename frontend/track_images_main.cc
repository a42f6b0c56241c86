// track_images: the image front end and a pose tracker over a stereo image sequence.
//
//   track_images --path DIR [--dataset auto|asl|euroc|kitti] --method NAME --output traj.tum
//                [--save-observations seq.json] [--viz DIR] [--frames A:B]
//                [--config frontend.json] [--tracker-config tracker.json] [--log frames.csv]
//
// Reads the stereo pairs one at a time (frontend/image_sequence.h), runs the front end
// (frontend/stereo_frontend.h) with detection when the tracker asks for new lines, and the
// tracker on its output. Writes the trajectory (TUM, camera-to-world), optionally the
// observations (stereo-lines/1, replayable with `track`), a per-frame log and the pictures of
// --viz (frontend/frontend_viz.h). All outputs or none: the trajectory, the observations and
// the log are streamed to temporary files (AtomicFileWriter) and put in place at the end, so
// memory stays flat over any length (--viz keeps one number per frame for its Fig. 9 curve).
#include <CLI/CLI.hpp>
#include <array>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <sstream>

#include "common/command_line.h"
#include "common/csv.h"
#include "common/file_io.h"
#include "common/json_reader.h"
#include "common/progress_bar.h"
#include "common/table.h"
#include "dataset/stereo_lines_io.h"
#include "dataset/trajectory.h"
#include "frontend/frontend_viz.h"
#include "frontend/image_sequence.h"
#include "frontend/image_tracking.h"
#include "methods/pose_tracker.h"

namespace {

// "A:B" -> [A, B) clamped to the sequence; "" -> everything. Throws on a malformed range.
std::pair<int, int> ParseFrames(const std::string& text, int size) {
  if (text.empty()) return {0, size};
  const size_t colon = text.find(':');
  if (colon == std::string::npos) throw CLI::ValidationError("--frames", "expected A:B, got '" + text + "'");
  const std::string a = text.substr(0, colon), b = text.substr(colon + 1);
  int first = 0, end = size;
  try {
    if (!a.empty()) first = slt::ParseInteger<int>(a);
    if (!b.empty()) end = slt::ParseInteger<int>(b);
  } catch (const std::invalid_argument&) {
    throw CLI::ValidationError("--frames", "expected A:B with integers, got '" + text + "'");
  }
  if (first < 0 || end <= first) throw CLI::ValidationError("--frames", "empty or negative range '" + text + "'");
  if (first >= size) {
    throw CLI::ValidationError("--frames", "starts at " + std::to_string(first) + " but the sequence has " +
                                               std::to_string(size) + " pairs");
  }
  return {first, std::min(end, size)};
}

}  // namespace

int main(int argc, char** argv) {
  using namespace slt;
  CLI::App app{"Track the stereo camera from an image sequence: line front end + pose tracker (TUM trajectory out)."};
  std::string path, dataset = "auto", method, output, observations_path, viz_dir, frames_text, config_path,
      tracker_config_path, log_path;
  bool progress_forced = false;
  app.add_option("--path,-p", path, "Sequence folder (ASL/EuRoC layout as `simulate --images` writes, or KITTI)")->required();
  app.add_option("--dataset", dataset, "Layout: auto, asl (= euroc) or kitti");
  app.add_option("--output,-o", output, "Trajectory to write, TUM format (camera-to-world)")->required();
  app.add_option("--save-observations", observations_path, "Also write the front end's observations, stereo-lines/1");
  app.add_option("--viz", viz_dir, "Write pictures (Figs. 7-9 of the paper) into this folder");
  app.add_option("--frames", frames_text, "Pairs A:B (A included, B excluded; either may be omitted)");
  app.add_option("--config,-c", config_path, "Front-end options, JSON (docs/frontend.md)");
  AddTrackerOptions(app, &method, &tracker_config_path, "--tracker-config")->required();
  app.add_option("--log", log_path, "Per-frame CSV: frame, time, status, lines, detection, stage times");
  app.add_flag("--progress", progress_forced, "Show progress even when stderr is not a terminal");
  if (const int exit_code = ParseCommandLine(app, argc, argv, "track_images"); exit_code >= 0) return exit_code;

  return RunProgram("track_images", [&] {
    cv::setNumThreads(1);  // single thread, as measured
    const FrontEndOptions options = FrontEndOptionsFromJson(ReadOptionsFile(config_path), config_path);
    std::unique_ptr<PoseTracker> tracker = CreateTracker(method, ReadOptionsFile(tracker_config_path), tracker_config_path);
    const std::unique_ptr<StereoImageSource> source = OpenStereoImages(path, DatasetLayoutFromName(dataset));
    const auto [first, end] = ParseFrames(frames_text, source->size());
    const StereoRig& rig = source->rig();
    std::fprintf(stderr, "track_images: %s; frames %d to %d\n", source->Describe().c_str(), first, end - 1);

    const std::vector<std::pair<std::string, std::string>> outputs = {
        {"--output", output}, {"--save-observations", observations_path}, {"--log", log_path}};
    CheckOutputsBeforeWork(outputs, {path, config_path, tracker_config_path});
    // The pictures replace --viz DIR whole: not a folder of the user's own files, nor one that
    // holds an input or another output.
    if (!viz_dir.empty()) {
      CheckReplaceableDirectory("--viz", viz_dir, FrontEndPictures::kMarkerFile, "track_images");
      std::vector<std::pair<std::string, std::string>> paths = {
          {"--path", path}, {"--config", config_path}, {"--tracker-config", tracker_config_path}};
      paths.insert(paths.end(), outputs.begin(), outputs.end());
      RefusePathsInReplacedDirectory("--viz", viz_dir, paths);
    }
    std::optional<StereoLinesWriter> writer;
    if (!observations_path.empty()) writer.emplace(observations_path, rig);
    std::optional<FrontEndPictures> pictures;
    if (!viz_dir.empty()) pictures.emplace(viz_dir, rig, end - first);

    StereoFrontEnd front_end(options, rig);
    ImageTracker image_tracker(front_end, *tracker, rig);
    TumTrajectoryWriter trajectory(output);
    // --log is streamed (memory stays flat over any length) and put in place at the end.
    std::optional<AtomicFileWriter> log_file;
    if (!log_path.empty()) {
      log_file.emplace(log_path);
      std::ostream& log = log_file->stream();
      log << "frame,time,status,lines,detected,added,lost,predicted,rematched,detect_ms,describe_ms,match_ms,track_ms,filter_ms,tracker_ms,read_ms";
      // The lost lines by reason (LineLoss, line_tracking.h), after the columns above.
      for (int r = 1; r < kNumLineLosses; ++r) log << ",lost_" << LineLossName(static_cast<LineLoss>(r));
      log << "\n";
    }
    std::array<long, kNumLineLosses> lost_by{};
    RunCounts counts;
    ProgressBar progress(progress_forced || StderrIsTerminal());
    int detection_frames = 0;
    FrontEndStageTimes steady, detecting;
    int steady_frames = 0;
    double tracker_seconds = 0.0, read_seconds = 0.0;
    const auto start = std::chrono::steady_clock::now();
    for (int k = first; k < end; ++k) {
      const auto t_read = std::chrono::steady_clock::now();
      const StereoImages images = source->Read(k);
      const double read = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_read).count();
      read_seconds += read;
      const ImageTrackingStep step = image_tracker.Step(images.left, images.right, images.time);
      const FrontEndFrameStats& stats = front_end.last_stats();
      tracker_seconds += step.tracker_seconds;
      if (stats.detected) {
        ++detection_frames;
        detecting += stats.times;
      } else {
        ++steady_frames;
        steady += stats.times;
      }
      counts.Add(step.output);
      trajectory.Append({images.time, step.output.cam_from_world.Inverse()});
      if (writer) writer->Append(*step.frame);
      if (pictures) pictures->AddFrame(k - first, images.left, images.right, front_end, *step.frame, step.output);
      for (int r = 1; r < kNumLineLosses; ++r) lost_by[r] += stats.lost_by[r];
      if (log_file) {
        const FrontEndStageTimes& t = stats.times;
        std::ostream& log = log_file->stream();
        log << k << "," << images.time << "," << TrackingStatusName(step.output.status) << "," << stats.live << ","
            << (stats.detected ? 1 : 0) << "," << stats.added << "," << stats.lost() << "," << stats.predicted << ","
            << stats.rematched << "," << 1e3 * t.detect << "," << 1e3 * t.describe << "," << 1e3 * t.match << ","
            << 1e3 * t.track << "," << 1e3 * t.filter << "," << 1e3 * step.tracker_seconds << "," << 1e3 * read;
        for (int r = 1; r < kNumLineLosses; ++r) log << "," << stats.lost_by[r];
        log << "\n";
      }
      if (progress.shown()) {
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const int done = k - first + 1;
        progress.Update(static_cast<size_t>(done), static_cast<size_t>(end - first),
                        StringPrintf(" %.1f fps  %d lines ", done / std::max(elapsed, 1e-9), stats.live));
      }
    }
    trajectory.Close();
    if (writer) writer->Close();
    if (log_file) log_file->Commit();
    if (pictures) pictures->Finish();

    const int frames = end - first;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const auto ms = [](double seconds, int n) { return n > 0 ? 1e3 * seconds / n : 0.0; };
    std::fprintf(stderr,
                 "track_images: %s: %d frames: %d tracking, %d degraded, %d new reference, %d lost; detection on %d frames\n"
                 "  per steady frame:    track %.2f ms, filter %.2f ms (front end %.2f ms)\n"
                 "  per detection frame: detect %.2f ms, describe %.2f ms, match %.2f ms, track %.2f ms, filter %.2f ms "
                 "(front end %.2f ms)\n"
                 "  tracker %.2f ms per frame, image reading %.2f ms per frame; %.1f fps overall\n",
                 method.c_str(), frames, counts.Frames(TrackingStatus::kTracking), counts.Frames(TrackingStatus::kDegraded),
                 counts.Frames(TrackingStatus::kNewReference), counts.Frames(TrackingStatus::kLost), detection_frames,
                 ms(steady.track, steady_frames), ms(steady.filter, steady_frames), ms(steady.Total(), steady_frames),
                 ms(detecting.detect, detection_frames), ms(detecting.describe, detection_frames),
                 ms(detecting.match, detection_frames), ms(detecting.track, detection_frames),
                 ms(detecting.filter, detection_frames), ms(detecting.Total(), detection_frames),
                 ms(tracker_seconds, frames), ms(read_seconds, frames), frames / std::max(wall, 1e-9));
    // Where the lines went: the tracks lost, by the stage that dropped them.
    std::string losses;
    long lost = 0;
    for (int r = 1; r < kNumLineLosses; ++r) {
      lost += lost_by[r];
      if (lost_by[r] > 0) {
        losses += StringPrintf("%s%s %ld", losses.empty() ? "" : ", ", LineLossName(static_cast<LineLoss>(r)), lost_by[r]);
      }
    }
    std::fprintf(stderr, "  lines lost: %ld%s%s%s\n", lost, losses.empty() ? "" : " (", losses.c_str(),
                 losses.empty() ? "" : ")");
    return 0;
  });
}
