// simulate: writes one synthetic stereo line sequence (docs/simulation.md).
//
//   simulate [CONFIG | -] --out DIR [--seed N] [--images [--layout L] [--threads N]]
//
// CONFIG is a path, or a bare name found in frontend/configs/ (the rendered scenes of
// docs/rendering.md: "room_752x480", "paper_640x480.json").
//
// DIR/seq.json              observations, stereo-lines/1 (the rig is the tracker's rig)
// DIR/gt.tum                ground truth, world_from_cam of the left camera, TUM
// DIR/scene.csv             the scene's 3-D segments (id,x1,y1,z1,x2,y2,z2, world frame, m)
// DIR/config.resolved.json  the config with every default filled in (and --seed applied)
// DIR/mav0/...              with --images: the rendered stereo images in EuRoC's ASL layout
//                           (docs/formats.md, docs/rendering.md); for the street scene (or
//                           --layout kitti) in KITTI odometry's instead: DIR/image_0, image_1,
//                           calib.txt, times.txt, poses.txt
#include <CLI/CLI.hpp>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/command_line.h"
#include "common/file_io.h"
#include "common/json_reader.h"
#include "common/machine_info.h"
#include "common/progress_bar.h"
#include "common/source_tree.h"
#include "dataset/stereo_lines_io.h"
#include "dataset/trajectory.h"
#include "render/sequence_renderer.h"
#include "simulator/simulator.h"

namespace {

// The scene as CSV, one segment per line (docs/formats.md): what scripts/plot_trajectory.py
// --scene draws. Numbers in the shortest form that reads back to the same double.
std::string SceneCsv(const std::vector<slt::Line3d>& lines) {
  std::string csv = "id,x1,y1,z1,x2,y2,z2\n";
  for (size_t id = 0; id < lines.size(); ++id) {
    csv += std::to_string(id);
    for (const Eigen::Vector3d* end : {&lines[id].p, &lines[id].q}) {
      for (int i = 0; i < 3; ++i) csv += "," + nlohmann::json((*end)(i)).dump();
    }
    csv += "\n";
  }
  return csv;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace slt;
  CLI::App app{"Simulate a synthetic stereo line sequence (observations and ground truth)."};
  std::string config_path, out_dir, seed_text;
  app.add_option("config", config_path,
                 "Simulation config, JSON: a path, or a name in frontend/configs/ (the rendered scenes); '-' reads "
                 "standard input; none gives the paper's protocol");
  app.add_option("--out,-o", out_dir, "Output directory (created if missing)")->required();
  // Read as text (ParseSeedOption).
  app.add_option("--seed", seed_text, "Base seed (0 .. 2^64-1), replacing the config's 'seed'");
  bool images = false;
  int threads = 0;
  app.add_flag("--images", images,
               "Also render the stereo images (DIR/mav0, EuRoC layout; the street: DIR/image_0 ..., KITTI layout)");
  std::string layout = "auto";
  app.add_option("--layout", layout, "Layout of the images: auto (KITTI for the street, else EuRoC), euroc, kitti")
      ->check(CLI::IsMember({"auto", "euroc", "kitti"}));
  app.add_option("--threads", threads, "Render threads (default: all cores); the images do not depend on it")
      ->check(CLI::Range(0, 4096));
  std::string scenes;
  for (const std::string& name : FileNamesIn("frontend/configs", ".json")) scenes += "\n  " + name;
  if (!scenes.empty()) app.footer("CONFIG names in frontend/configs/ (docs/rendering.md):" + scenes);
  std::optional<std::uint64_t> seed;
  const int exit_code = ParseCommandLine(app, argc, argv, "simulate", [&] {
    if (app.count("--seed") > 0) seed = ParseSeedOption("--seed", seed_text);
  });
  if (exit_code >= 0) return exit_code;

  try {
    nlohmann::json document = nlohmann::json::object();
    std::string where = "defaults";
    if (config_path == "-") {
      where = "<stdin>";
      document = ParseJson(std::cin, where);
    } else if (!config_path.empty()) {
      config_path = FindNamedFile(config_path, "frontend/configs", ".json", "simulation config");
      where = config_path;
      document = ReadJsonFile(config_path);
    }
    SimulationConfig config = SimulationConfigFromJson(document, where);
    if (seed) config.seed = *seed;
    const SimulatedSequence result = Simulate(config);

    const std::filesystem::path dir(out_dir);
    CreateDirectories(out_dir);
    const bool kitti = layout == "kitti" || (layout == "auto" && config.scene.type == SceneType::kStreet);
    std::vector<std::string> outputs = {(dir / "seq.json").string(), (dir / "gt.tum").string(),
                                        (dir / "scene.csv").string(), (dir / "config.resolved.json").string()};
    if (images && kitti) {
      for (const char* file : {"calib.txt", "times.txt", "poses.txt"}) outputs.push_back((dir / file).string());
    }
    for (const std::string& output : outputs) RefuseOutputThatIsInput("--out", output, {config_path});
    // All outputs or none: a failure after the first file removes the files this run writes.
    try {
      WriteStereoLines(outputs[0], result.sequence);
      WriteTumTrajectory(outputs[1], result.ground_truth);
      WriteTextFileAtomically(outputs[2], SceneCsv(result.lines));
      if (images) {
        // One OpenCV thread per render thread: the frames are the parallel work.
        cv::setNumThreads(1);
        const int workers = threads > 0 ? threads : std::max(1, CpuCores());
        // The progress bar on a terminal only: a log gets the closing line, not a line per frame.
        ProgressBar bar;
        const auto update = [&](int done, int total) {
          bar.Update(static_cast<size_t>(done), static_cast<size_t>(total), " frames rendered");
        };
        if (kitti) {
          WriteKittiSequence(out_dir, result, config, workers, update);
        } else {
          WriteEurocSequence(out_dir, result, config, workers, update);
        }
      }
      WriteJsonFile(outputs[3], SimulationConfigToJson(config));
    } catch (...) {
      std::error_code error;
      for (const std::string& output : outputs) std::filesystem::remove(output, error);
      throw;
    }

    std::size_t observations = 0;
    for (const StereoFrame& frame : result.sequence.frames) observations += frame.left.size() + frame.right.size();
    std::fprintf(stderr, "simulate: %s: %zu frames, %zu lines, %.1f observations per image\n", out_dir.c_str(),
                 result.sequence.frames.size(), result.lines.size(),
                 static_cast<double>(observations) / (2.0 * result.sequence.frames.size()));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "simulate: error: %s\n", e.what());
    return 1;
  }
}
