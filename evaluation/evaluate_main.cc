// evaluate: accuracy of an estimated trajectory against the ground truth (docs/metrics.md).
//
//   evaluate GT EST [-a | -as | --alignment none|se3|sim3] [--max-time-diff S] [--rpe-delta N]
//            [--rpe-all-pairs] [--gt-format tum|kitti] [--est-format tum|kitti]
//            [--kitti-frame-period S] [--format table|json] [--json FILE] [--per-frame]
//            [--plot FILE.png] [--strict]
//            [--covariance LOG]
//            [--kitti [--kitti-lengths 100,200,...]]
//
// GT and EST may also be given as --gt and --est. Prints a table of the errors (evo's
// statistics with units) or, with --format json, the JSON that --json writes. Warns when fewer
// than 95 % of either trajectory's poses are associated (an error with --strict). Exit codes:
// 0 success, 1 unreadable or unusable data (or the warning under --strict), 2 bad command line.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>

#include "common/command_line.h"
#include "common/file_io.h"
#include "common/json_reader.h"
#include "common/source_tree.h"
#include "dataset/trajectory.h"
#include "evaluation/consistency.h"
#include "evaluation/metrics.h"
#include "evaluation/report.h"

namespace {

namespace fs = std::filesystem;

slt::Trajectory ReadTrajectory(const std::string& path, const std::string& format, double kitti_frame_period) {
  return format == "kitti" ? slt::ReadKittiTrajectory(path, kitti_frame_period) : slt::ReadTumTrajectory(path);
}

// A temporary directory removed when it goes out of scope.
class TemporaryDirectory {
 public:
  TemporaryDirectory() : path_(fs::temp_directory_path() / ("slt_evaluate_" + std::to_string(::getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TemporaryDirectory() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  std::string File(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

// Draws the plan and side views of the ground truth and of the estimate as it was measured
// (aligned), and the error against time, with scripts/plot_trajectory.py.
void Plot(const std::string& png, const slt::Trajectory& gt, slt::Trajectory est, const slt::TrajectoryErrors& errors,
          const std::string& gt_path, const std::string& est_path) {
  TemporaryDirectory tmp;
  for (slt::TimedPose& pose : est) pose.world_from_cam = errors.alignment.Apply(pose.world_from_cam);
  slt::WriteTumTrajectory(tmp.File("gt.tum"), gt);
  slt::WriteTumTrajectory(tmp.File("est.tum"), est);
  slt::WriteJsonFile(tmp.File("errors.json"), slt::ToJson(errors, /*include_per_frame=*/true));
  const std::string est_label = errors.options.alignment == slt::Alignment::kNone
                                    ? "estimate"
                                    : std::string("estimate, aligned (") + slt::AlignmentName(errors.options.alignment) + ")";
  slt::RunPythonScript("scripts/plot_trajectory.py",
                       {tmp.File("gt.tum"), tmp.File("est.tum"), "--reference", "--labels", "ground truth",
                        est_label, "--errors", tmp.File("errors.json"), "--out", png, "--title",
                        est_path + " against " + gt_path + " (alignment " +
                            slt::AlignmentName(errors.options.alignment) + ")"});
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Accuracy of an estimated camera trajectory against the ground truth: ATE, RPE and final "
               "errors, defined as evo defines them (docs/metrics.md). Prints a table; --format json or "
               "--json FILE for JSON."};
  std::string gt_path, est_path, json_path, plot_path;
  std::string gt_format = "tum", est_format = "tum", alignment, print_format = "table";
  slt::EvaluationOptions options;
  double kitti_frame_period = 0.1;
  bool per_frame = false, align = false, correct_scale = false, strict = false;
  app.add_option("gt,--gt", gt_path, "Ground-truth trajectory (world_from_cam of the left camera)")->required();
  app.add_option("est,--est", est_path, "Estimated trajectory")->required();
  app.add_option("--gt-format", gt_format, "Format of the ground truth")
      ->check(CLI::IsMember({"tum", "kitti"}))
      ->capture_default_str();
  app.add_option("--est-format", est_format, "Format of the estimate")
      ->check(CLI::IsMember({"tum", "kitti"}))
      ->capture_default_str();
  app.add_option("--kitti-frame-period", kitti_frame_period, "Seconds between KITTI poses (they have no times)")
      ->capture_default_str();
  app.add_flag("-a,--align", align, "Align the estimate to the ground truth with an SE(3) transform (as evo's -a)");
  app.add_flag("-s,--correct-scale", correct_scale, "With -a: a Sim(3) alignment, scale included (-as, as evo's)");
  app.add_option("--alignment", alignment, "The alignment by name (default none); the same as -a (se3) or -as (sim3)")
      ->check(CLI::IsMember({"none", "se3", "sim3"}));
  app.add_option("--max-time-diff", options.max_time_diff_s, "Association window in seconds")->capture_default_str();
  app.add_option("--rpe-delta", options.rpe_delta_frames, "RPE step in frames")->capture_default_str();
  app.add_flag("--rpe-all-pairs", options.rpe_all_pairs, "RPE over every pair (i, i + delta), not only i = k delta");
  app.add_option("--format", print_format, "What to print: the table or the JSON")
      ->check(CLI::IsMember({"table", "json"}))
      ->capture_default_str();
  app.add_option("--json,--out", json_path, "Write the metrics as JSON to this file");
  app.add_flag("--per-frame", per_frame, "Include the per-frame error curve in the JSON");
  app.add_option("--plot", plot_path, "Draw plan and side views and the error against time to this PNG");
  app.add_flag("--strict", strict, "Fail when fewer than 95 % of either trajectory's poses are associated");
  std::string covariance_path;
  app.add_option("--covariance", covariance_path,
                 "The tracker's `track --log` file: adds the consistency of its pose covariance (NEES, errors "
                 "beyond 3 sigma; no alignment)");
  bool kitti_metric = false;
  slt::KittiOdometryOptions kitti_options;
  app.add_flag("--kitti", kitti_metric,
               "Also the KITTI odometry metric (\"kitti_odometry\": translation % and rotation deg/m over segments)");
  app.add_option("--kitti-lengths", kitti_options.segment_lengths_m, "With --kitti: segment lengths in m")
      ->delimiter(',')
      ->capture_default_str();

  const int exit_code = slt::ParseCommandLine(app, argc, argv, "evaluate", [&] {
    // Checked here rather than with CLI11's range validators, whose messages print the whole
    // range of a double.
    if (!(kitti_frame_period > 0.0) || !std::isfinite(kitti_frame_period)) {
      throw CLI::ValidationError("--kitti-frame-period", "must be a finite number > 0");
    }
    if (!(options.max_time_diff_s >= 0.0) || !std::isfinite(options.max_time_diff_s)) {
      throw CLI::ValidationError("--max-time-diff", "must be a finite number >= 0");
    }
    if (options.rpe_delta_frames < 1) throw CLI::ValidationError("--rpe-delta", "must be >= 1");
    if (correct_scale && !align) {
      throw CLI::ValidationError("-s/--correct-scale", "needs -a (-as: Sim(3) alignment); a scale-only alignment is not offered");
    }
    if (align && !alignment.empty()) throw CLI::ValidationError("--alignment", "give either -a/-as or --alignment");
    if (!plot_path.empty() && fs::path(plot_path).extension() != ".png") {
      throw CLI::ValidationError("--plot", "expected a file name ending in .png");
    }
  });
  if (exit_code >= 0) return exit_code;
  if (align) alignment = correct_scale ? "sim3" : "se3";
  if (alignment.empty()) alignment = "none";

  try {
    options.alignment = slt::AlignmentFromName(alignment);
    if (!json_path.empty()) {
      slt::RefuseOutputThatIsInput("--json", json_path, {gt_path, est_path});
      slt::CheckWritable("--json", json_path);
    }
    if (!plot_path.empty()) slt::RefuseOutputThatIsInput("--plot", plot_path, {gt_path, est_path, json_path});
    const slt::Trajectory gt = ReadTrajectory(gt_path, gt_format, kitti_frame_period);
    const slt::Trajectory est = ReadTrajectory(est_path, est_format, kitti_frame_period);
    slt::TrajectoryErrors errors;
    try {
      errors = slt::EvaluateTrajectory(gt, est, options);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(est_path + " against " + gt_path + ": " + e.what());
    }
    const std::string warning = slt::AssociationWarning(errors);
    if (!warning.empty()) {
      if (strict) throw std::runtime_error(est_path + " against " + gt_path + ": " + warning + " (--strict)");
      std::fprintf(stderr, "evaluate: warning: %s against %s: %s\n", est_path.c_str(), gt_path.c_str(), warning.c_str());
    }
    nlohmann::json metrics = slt::ToJson(errors, per_frame);
    if (!covariance_path.empty()) {
      try {
        metrics["consistency"] = slt::ToJson(slt::EvaluateConsistency(
            gt, est, slt::ReadLogCovariances(covariance_path), options.max_time_diff_s));
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(covariance_path + ": " + e.what());
      }
    }
    // The readers bound every value, so this is a defect, not bad input: never print a NaN
    // (dumped as null) as if it were a measurement.
    const std::string non_finite = slt::FindNonFiniteNumber(metrics);
    if (!non_finite.empty()) {
      throw std::runtime_error(est_path + " against " + gt_path + ": metric '" + non_finite + "' is not finite");
    }
    // After the check: a sequence shorter than every segment length has no KITTI segment, and
    // its means are null by design (docs/metrics.md).
    if (kitti_metric) {
      kitti_options.max_time_diff_s = options.max_time_diff_s;
      kitti_options.Check("--kitti-lengths");
      metrics["kitti_odometry"] = slt::ToJson(slt::EvaluateKittiOdometry(gt, est, kitti_options));
    }
    metrics["warnings"] = warning.empty() ? nlohmann::json::array() : nlohmann::json::array({warning});
    // Every output or none: the plot (the step most likely to fail) first.
    if (!plot_path.empty()) Plot(plot_path, gt, est, errors, gt_path, est_path);
    if (!json_path.empty()) slt::WriteJsonFile(json_path, metrics);
    if (print_format == "json") {
      std::cout << metrics.dump(2) << "\n";
    } else {
      std::cout << est_path << " against " << gt_path << "\n" << slt::ErrorTable(errors);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "evaluate: error: %s\n", e.what());
    return 1;
  }
}
