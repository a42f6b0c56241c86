// evaluate: accuracy of an estimated trajectory against the ground truth (docs/metrics.md).
//
//   evaluate --gt gt.tum --est traj.tum [--align none|se3|sim3] [--max-time-diff S]
//            [--rpe-delta N] [--rpe-all-pairs] [--gt-format tum|kitti] [--est-format tum|kitti]
//            [--kitti-frame-period S] [--per-frame] [--out metrics.json]
//            [--kitti [--kitti-lengths 100,200,...]]
//
// Prints the metrics as JSON on stdout (and to --out). Exit codes: 0 success, 1 unreadable or
// unusable data, 2 bad command line.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include "common/json_reader.h"
#include "dataset/trajectory.h"
#include "evaluation/metrics.h"

namespace {

slt::Trajectory ReadTrajectory(const std::string& path, const std::string& format, double kitti_frame_period) {
  return format == "kitti" ? slt::ReadKittiTrajectory(path, kitti_frame_period) : slt::ReadTumTrajectory(path);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Accuracy of an estimated camera trajectory against the ground truth: ATE, RPE, final and "
               "per-frame errors, defined as evo defines them (docs/metrics.md). Prints JSON."};
  std::string gt_path, est_path, out_path;
  std::string gt_format = "tum", est_format = "tum", alignment = "none";
  slt::EvaluationOptions options;
  double kitti_frame_period = 0.1;
  bool per_frame = false;
  app.add_option("--gt", gt_path, "Ground-truth trajectory (world_from_cam of the left camera)")->required();
  app.add_option("--est", est_path, "Estimated trajectory")->required();
  app.add_option("--gt-format", gt_format, "Format of --gt")
      ->check(CLI::IsMember({"tum", "kitti"}))
      ->capture_default_str();
  app.add_option("--est-format", est_format, "Format of --est")
      ->check(CLI::IsMember({"tum", "kitti"}))
      ->capture_default_str();
  app.add_option("--kitti-frame-period", kitti_frame_period, "Seconds between KITTI poses (they have no times)")
      ->capture_default_str();
  app.add_option("--align", alignment, "Align the estimate to the ground truth before measuring")
      ->check(CLI::IsMember({"none", "se3", "sim3"}))
      ->capture_default_str();
  app.add_option("--max-time-diff", options.max_time_diff_s, "Association window in seconds")->capture_default_str();
  app.add_option("--rpe-delta", options.rpe_delta_frames, "RPE step in frames")->capture_default_str();
  app.add_flag("--rpe-all-pairs", options.rpe_all_pairs, "RPE over every pair (i, i + delta), not only i = k delta");
  app.add_flag("--per-frame", per_frame, "Include the per-frame error curve");
  app.add_option("--out", out_path, "Also write the JSON to this file");
  bool kitti_metric = false;
  slt::KittiOdometryOptions kitti_options;
  app.add_flag("--kitti", kitti_metric,
               "Also the KITTI odometry metric (\"kitti_odometry\": translation % and rotation deg/m over segments)");
  app.add_option("--kitti-lengths", kitti_options.segment_lengths_m, "With --kitti: segment lengths in m")
      ->delimiter(',')
      ->capture_default_str();

  try {
    app.parse(argc, argv);
    // Checked here rather than with CLI11's range validators, whose messages print the whole
    // range of a double.
    if (!(kitti_frame_period > 0.0) || !std::isfinite(kitti_frame_period)) {
      throw CLI::ValidationError("--kitti-frame-period", "must be a finite number > 0");
    }
    if (!(options.max_time_diff_s >= 0.0) || !std::isfinite(options.max_time_diff_s)) {
      throw CLI::ValidationError("--max-time-diff", "must be a finite number >= 0");
    }
    if (options.rpe_delta_frames < 1) throw CLI::ValidationError("--rpe-delta", "must be >= 1");
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "evaluate: error: %s\n", e.what());
    return 2;
  }

  try {
    options.alignment = slt::AlignmentFromName(alignment);
    const slt::Trajectory gt = ReadTrajectory(gt_path, gt_format, kitti_frame_period);
    const slt::Trajectory est = ReadTrajectory(est_path, est_format, kitti_frame_period);
    slt::TrajectoryErrors errors;
    try {
      errors = slt::EvaluateTrajectory(gt, est, options);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(est_path + " against " + gt_path + ": " + e.what());
    }
    nlohmann::json metrics = slt::ToJson(errors, per_frame);
    if (kitti_metric) {
      kitti_options.max_time_diff_s = options.max_time_diff_s;
      kitti_options.Check("--kitti-lengths");
      metrics["kitti_odometry"] = slt::ToJson(slt::EvaluateKittiOdometry(gt, est, kitti_options));
    }
    if (!out_path.empty()) slt::WriteJsonFile(out_path, metrics);
    std::cout << metrics.dump(2) << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "evaluate: error: %s\n", e.what());
    return 1;
  }
}
