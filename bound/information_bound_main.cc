// information_bound: the accuracy a causal tracker could reach at all on an experiment
// config's simulated trials (bound/information_bound.h; docs/long_sequences.md). For every
// sweep point and trial (the sequences run_experiment simulates: seed TrialSeed(seed, k)) it
// computes the full-history bundle adjustment's pose at every keyframe, causally and as a
// smoother, and optionally a method of the config at the same keyframes, and writes
//   DIR/errors.csv   point, trial, estimator, frame, ex, ey, ez (m, world axes; y down)
//   DIR/summary.csv  per point, trial and estimator: ATE (RMSE over the keyframes), maximum
//                    error, per-axis RMS, path length, the worst keyframe and its error.
//
//   information_bound CONFIG [--out DIR] [--trials N] [--first-trial K] [--points P...]
//                     [--threads N] [--options JSON] [--method ID]
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "common/command_line.h"
#include "common/csv.h"
#include "common/file_io.h"
#include "common/json_reader.h"
#include "common/parallel.h"
#include "experiments/experiment_config.h"
#include "experiments/experiment_driver.h"
#include "bound/information_bound.h"
#include "methods/pose_tracker.h"

namespace slt {
namespace {

struct Errors {
  double ate_m = 0.0, max_m = 0.0;
  Eigen::Vector3d rms_m = Eigen::Vector3d::Zero();
  int worst_frame = -1;
  Eigen::Vector3d worst_m = Eigen::Vector3d::Zero();
};

// Camera-centre errors at `frames` (world axes), as evaluate's trans_err_m without alignment.
Errors ErrorsAt(const SimulatedSequence& sim, const std::vector<int>& frames, const std::vector<Rigid3d>& cam_from_world,
                const std::vector<std::string>& row_prefix, std::string* rows) {
  Errors e;
  for (size_t n = 0; n < frames.size(); ++n) {
    const Eigen::Vector3d d = cam_from_world[n].Center() - sim.ground_truth[frames[n]].world_from_cam.translation;
    e.ate_m += d.squaredNorm();
    e.rms_m += d.cwiseAbs2();
    if (d.norm() > e.max_m) {
      e.max_m = d.norm();
      e.worst_frame = frames[n];
      e.worst_m = d;
    }
    if (rows) {
      std::vector<std::string> row = row_prefix;
      for (const std::string& field : {std::to_string(frames[n]), FormatDouble(d.x()), FormatDouble(d.y()), FormatDouble(d.z())}) {
        row.push_back(field);
      }
      *rows += CsvLine(row);
    }
  }
  const double count = static_cast<double>(std::max<size_t>(1, frames.size()));
  e.ate_m = std::sqrt(e.ate_m / count);
  e.rms_m = (e.rms_m / count).cwiseSqrt();
  return e;
}

double PathLength(const SimulatedSequence& sim) {
  double length = 0.0;
  for (size_t f = 1; f < sim.ground_truth.size(); ++f) {
    length += (sim.ground_truth[f].world_from_cam.translation - sim.ground_truth[f - 1].world_from_cam.translation).norm();
  }
  return length;
}

}  // namespace
}  // namespace slt

int main(int argc, char** argv) {
  using namespace slt;
  CLI::App app{"The full-history bundle adjustment bound (causal and smoother) on an experiment config's simulated trials."};
  std::string config_arg, out_dir = "information_bound", method_id, options_text = "{}";
  int trials = 0, first_trial = 0, threads = 1;
  std::vector<int> points_arg;
  app.add_option("config", config_arg, "Experiment config: a path or a name in experiments/configs/")->required();
  app.add_option("--out,-o", out_dir, "Output directory");
  app.add_option("--trials", trials, "Trials (default: the config's)")->check(CLI::Range(1, 1000000));
  app.add_option("--first-trial", first_trial, "First trial")->check(CLI::Range(0, 1000000));
  app.add_option("--points", points_arg, "Sweep points (indices; default: all)");
  app.add_option("--threads", threads, "Worker threads (one trial each)")->check(CLI::Range(1, 4096));
  app.add_option("--options", options_text, "Bound options, JSON (information_bound.h; missing keys keep their defaults)");
  app.add_option("--method", method_id, "Also a method of the config (its id), evaluated at the same keyframes");
  const int parsed = ParseCommandLine(app, argc, argv, "information_bound");
  if (parsed >= 0) return parsed;
  return RunProgram("information_bound", [&] {
    InformationBoundOptions options;
    JsonReader reader(nlohmann::json::parse(options_text), "--options");
    InformationBoundOptionsSchema().Read(reader, &options);
    reader.RejectUnknownKeys();
    const ExperimentConfig config = ReadExperimentConfig(FindConfigFile(config_arg));
    const std::vector<SweepPoint> points = ExpandSweep(config.sweep);
    if (points_arg.empty()) {
      for (size_t p = 0; p < points.size(); ++p) points_arg.push_back(static_cast<int>(p));
    }
    for (int p : points_arg) {
      if (p < 0 || p >= static_cast<int>(points.size())) throw CLI::ValidationError("--points", "no point " + std::to_string(p));
    }
    const int method = method_id.empty() ? -1 : MethodIndex(config, method_id);
    if (!method_id.empty() && method < 0) throw CLI::ValidationError("--method", "no method '" + method_id + "' in the config");
    if (trials == 0) trials = config.trials;

    struct Job {
      int point, trial;
      std::string rows, summary;
    };
    std::vector<Job> jobs;
    for (int p : points_arg) {
      for (int k = first_trial; k < first_trial + trials; ++k) jobs.push_back({p, k, "", ""});
    }
    ParallelFor(jobs.size(), threads, [&](size_t j) {
      Job& job = jobs[j];
      const SimulationConfig simulation = TrialSimulation(config, points[job.point], job.trial);
      const SimulatedSequence sim = Simulate(simulation);
      const InformationBound bound = ComputeInformationBound(sim, options);
      const double path_m = PathLength(sim);
      const auto report = [&](const std::string& estimator, const std::vector<int>& frames, const std::vector<Rigid3d>& poses,
                              bool rows) {
        if (poses.empty()) return;
        const Errors e = ErrorsAt(sim, frames, poses, {std::to_string(job.point), std::to_string(job.trial), estimator},
                                  rows ? &job.rows : nullptr);
        job.summary += CsvLine({std::to_string(job.point), std::to_string(job.trial), estimator, FormatDouble(e.ate_m),
                                FormatDouble(e.max_m), FormatDouble(e.rms_m.x()), FormatDouble(e.rms_m.y()),
                                FormatDouble(e.rms_m.z()), FormatDouble(path_m), std::to_string(e.worst_frame),
                                FormatDouble(e.worst_m.x()), FormatDouble(e.worst_m.y()), FormatDouble(e.worst_m.z()),
                                std::to_string(bound.unsolved), std::to_string(bound.iterations), std::to_string(simulation.seed)});
      };
      report("causal", bound.frames, bound.causal_cam_from_world, true);
      report("smoother", bound.frames, bound.smoother_cam_from_world, true);
      if (method >= 0) {
        const MethodSpec& m = config.methods[method];
        std::unique_ptr<PoseTracker> tracker = CreateTracker(m.name, m.options, config.name + ": method '" + m.Id() + "' options");
        const std::vector<TrackedFrame> tracked = TrackSequence(*tracker, sim.sequence);
        std::vector<Rigid3d> at_keyframes, every;
        std::vector<int> all_frames;
        for (const int f : bound.frames) at_keyframes.push_back(tracked[f].output.cam_from_world);
        for (size_t f = 0; f < tracked.size(); ++f) {
          every.push_back(tracked[f].output.cam_from_world);
          all_frames.push_back(static_cast<int>(f));
        }
        report("method", bound.frames, at_keyframes, true);
        report("method_all_frames", all_frames, every, false);  // run_experiment's ATE and maximum
      }
      std::fprintf(stderr, "information_bound: %s, trial %d done\n", PointText(config, points[job.point]).c_str(), job.trial);
    });
    std::string rows = "point,trial,estimator,frame,ex,ey,ez\n";
    std::string summary =
        "point,trial,estimator,ate_m,max_m,rms_x_m,rms_y_m,rms_z_m,path_m,worst_frame,worst_x_m,worst_y_m,worst_z_m,unsolved,iterations,seed\n";
    for (const Job& job : jobs) {
      rows += job.rows;
      summary += job.summary;
    }
    CreateDirectories(out_dir);
    WriteTextFileAtomically(JoinPath(out_dir, "errors.csv"), rows);
    WriteTextFileAtomically(JoinPath(out_dir, "summary.csv"), summary);
    return 0;
  });
}
