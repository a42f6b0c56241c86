// track: runs one registered tracker over a stereo-lines/1 sequence and writes its trajectory.
//
//   track --method trifocal_line_ekf --input seq.json --output traj.tum [--config tracker.json]
//         (--tracker-config: the same option under the name track_images and measure_frontend use)
//         [--kitti traj.kitti] [--log frames.csv] [--print-config]
//   track --list
//   track --method NAME --list-options
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <utility>
#include <vector>

#include "common/csv.h"
#include "common/command_line.h"
#include "common/file_io.h"
#include "common/json_reader.h"
#include "dataset/stereo_lines_io.h"
#include "dataset/trajectory.h"
#include "methods/pose_tracker.h"

int main(int argc, char** argv) {
  using namespace slt;
  CLI::App app{"Run a pose tracker over a stereo-lines/1 sequence and write its trajectory (TUM, camera-to-world)."};
  std::string method, input, output, config_path, kitti_path, log_path;
  bool list = false, print_config = false, list_options = false;
  AddTrackerOptions(app, &method, &config_path, "--config,-c,--tracker-config");
  app.add_option("--input,-i", input, "Observations, stereo-lines/1 JSON");
  app.add_option("--output,-o", output, "Trajectory to write, TUM format");
  app.add_option("--kitti", kitti_path, "Also write the trajectory in KITTI format");
  app.add_option("--log", log_path, "Per-frame CSV: frame, time, status, reason, features used and left out by reason, time per frame, pose covariance");
  app.add_flag("--list", list, "List the registered trackers and exit");
  app.add_flag("--print-config", print_config, "Print the tracker's resolved options (JSON) and exit");
  app.add_flag("--list-options", list_options, "List the tracker's options (key, default, allowed values, doc) and exit");
  if (const int exit_code = ParseCommandLine(app, argc, argv, "track"); exit_code >= 0) return exit_code;

  return RunProgram("track", [&] {
    if (list) {
      for (const TrackerInfo& info : RegisteredTrackers()) {
        std::cout << info.name << "\t" << info.description << "\n";
      }
      return 0;
    }
    if (method.empty()) throw CLI::RequiredError("--method");
    if (list_options) {
      const TrackerInfo& info = FindTracker(method);
      std::cout << (info.list_options ? FormatOptionDocs(info.list_options()) : method + " takes no options\n");
      return 0;
    }
    auto tracker = CreateTracker(method, ReadOptionsFile(config_path), config_path);
    if (print_config) {
      std::cout << tracker->Options().dump(2) << "\n";
      return 0;
    }
    if (input.empty()) throw CLI::RequiredError("--input");
    if (output.empty()) throw CLI::RequiredError("--output");
    // Every output is checked before the (possibly long) tracking: none may be an input or
    // another output, and each must be writable.
    CheckOutputsBeforeWork({{"--output", output}, {"--kitti", kitti_path}, {"--log", log_path}}, {input, config_path});
    // Frame by frame: memory does not grow with the observations of a long sequence.
    StereoLinesReader reader(input);
    tracker->Reset(reader.rig());
    Trajectory trajectory;
    std::ostringstream log;
    // The covariance of each pose (TrackerOutput::covariance, docs/formats.md): its upper
    // triangle, row by row, cov_<i><j> for i <= j; empty when the tracker has none.
    log << "frame,time,status,reason,features_available,features_used,features_unmatched,features_degenerate,"
           "features_outside_gate,time_us";
    for (int i = 0; i < 6; ++i) {
      for (int j = i; j < 6; ++j) log << ",cov_" << i << j;
    }
    log << "\n";
    RunCounts counts;
    double total_us = 0.0;
    StereoFrame frame;
    for (size_t k = 0; reader.Next(&frame); ++k) {
      const TrackedFrame tracked = TrackFrame(*tracker, frame);
      const TrackerOutput& out = tracked.output;
      total_us += tracked.time_us;
      counts.Add(out);
      trajectory.push_back({frame.time, out.cam_from_world.Inverse()});
      log << k << "," << frame.time << "," << TrackingStatusName(out.status) << "," << StatusReasonName(out.reason) << ","
          << out.features_available << "," << out.features_used << "," << out.features_unmatched << ","
          << out.features_degenerate << "," << out.features_outside_gate << "," << tracked.time_us;
      for (int i = 0; i < 6; ++i) {
        for (int j = i; j < 6; ++j) {
          log << "," << (out.has_covariance ? FormatDouble(out.covariance(i, j)) : std::string());
        }
      }
      log << "\n";
    }
    WriteTumTrajectory(output, trajectory);
    if (!kitti_path.empty()) WriteKittiTrajectory(kitti_path, trajectory);
    if (!log_path.empty()) WriteTextFileAtomically(log_path, log.str());
    std::fprintf(stderr,
                 "track: %s: %zu frames (%d tracking, %d new reference pairs, %d lost, %d degraded), %.1f us per frame\n",
                 method.c_str(), trajectory.size(), counts.Frames(TrackingStatus::kTracking),
                 counts.Frames(TrackingStatus::kNewReference), counts.Frames(TrackingStatus::kLost),
                 counts.Frames(TrackingStatus::kDegraded),
                 trajectory.empty() ? 0.0 : total_us / trajectory.size());
    // Why: frames by reason (the first frame's aside), then the features left out.
    std::string reasons;
    for (int r = static_cast<int>(StatusReason::kFewFeaturesLeft); r < kNumStatusReasons; ++r) {
      if (counts.by_reason[r] == 0) continue;
      reasons += std::string(reasons.empty() ? "" : ", ") + StatusReasonName(static_cast<StatusReason>(r)) + " " +
                 std::to_string(counts.by_reason[r]);
    }
    std::fprintf(stderr,
                 "track: reasons: %s; features left out over all frames: %ld not matched in both images, "
                 "%ld degenerate, %ld outside the gate\n",
                 reasons.empty() ? "none" : reasons.c_str(), counts.features_unmatched, counts.features_degenerate,
                 counts.features_outside_gate);
    return 0;
  });
}
