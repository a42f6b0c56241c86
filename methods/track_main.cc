// track: runs one registered tracker over a stereo-lines/1 sequence and writes its trajectory.
//
//   track --method trifocal_line_ekf --input seq.json --output traj.tum [--config tracker.json]
//         [--kitti traj.kitti] [--log frames.csv] [--print-config]
//   track --list
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "common/json_reader.h"
#include "dataset/stereo_lines_io.h"
#include "dataset/trajectory.h"
#include "methods/pose_tracker.h"

int main(int argc, char** argv) {
  using namespace slt;
  CLI::App app{"Run a pose tracker over a stereo-lines/1 sequence and write its trajectory (TUM, camera-to-world)."};
  std::string method, input, output, config_path, kitti_path, log_path;
  bool list = false, print_config = false;
  app.add_option("--method,-m", method, "Tracker name (see --list)");
  app.add_option("--input,-i", input, "Observations, stereo-lines/1 JSON");
  app.add_option("--output,-o", output, "Trajectory to write, TUM format");
  app.add_option("--config,-c", config_path, "Tracker options, JSON (missing keys keep their defaults)");
  app.add_option("--kitti", kitti_path, "Also write the trajectory in KITTI format");
  app.add_option("--log", log_path, "Per-frame CSV: frame, time, status, features, time per frame");
  app.add_flag("--list", list, "List the registered trackers and exit");
  app.add_flag("--print-config", print_config, "Print the tracker's resolved options (JSON) and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "track: error: %s (see --help)\n", e.what());
    return 2;
  }

  try {
    if (list) {
      for (const TrackerInfo& info : RegisteredTrackers()) {
        std::cout << info.name << "\t" << info.description << "\n";
      }
      return 0;
    }
    if (method.empty()) throw CLI::RequiredError("--method");
    const nlohmann::json options = config_path.empty() ? nlohmann::json::object() : ReadJsonFile(config_path);
    auto tracker = CreateTracker(method, options, config_path.empty() ? "--config" : config_path);
    if (print_config) {
      std::cout << tracker->Options().dump(2) << "\n";
      return 0;
    }
    if (input.empty()) throw CLI::RequiredError("--input");
    if (output.empty()) throw CLI::RequiredError("--output");
    const StereoSequence sequence = ReadStereoLines(input);
    const std::vector<TrackedFrame> run = TrackSequence(*tracker, sequence);

    Trajectory trajectory;
    trajectory.reserve(sequence.frames.size());
    std::ostringstream log;
    log << "frame,time,status,features_available,features_used,time_us\n";
    int counts[3] = {0, 0, 0};
    double total_us = 0.0;
    for (size_t k = 0; k < run.size(); ++k) {
      const TrackerOutput& out = run[k].output;
      const double time = sequence.frames[k].time;
      total_us += run[k].time_us;
      ++counts[static_cast<int>(out.status)];
      trajectory.push_back({time, out.cam_from_world.Inverse()});
      log << k << "," << time << "," << TrackingStatusName(out.status) << "," << out.features_available << ","
          << out.features_used << "," << run[k].time_us << "\n";
    }
    WriteTumTrajectory(output, trajectory);
    if (!kitti_path.empty()) WriteKittiTrajectory(kitti_path, trajectory);
    if (!log_path.empty()) WriteTextFileAtomically(log_path, log.str());
    std::fprintf(stderr, "track: %s: %zu frames (%d tracking, %d new reference pairs, %d lost), %.1f us per frame\n",
                 method.c_str(), sequence.frames.size(), counts[0], counts[1], counts[2],
                 sequence.frames.empty() ? 0.0 : total_us / sequence.frames.size());
    return 0;
  } catch (const CLI::Error& e) {
    std::fprintf(stderr, "track: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "track: error: %s\n", e.what());
    return 1;
  }
}
