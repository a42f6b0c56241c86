#include "bound/information_bound.h"

#include <ceres/problem.h>
#include <ceres/solver.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <memory>

#include "optim/ceres_logging.h"
#include "optim/line_sfm_manifolds.h"
#include "optim/taylor_segment_cost.h"

namespace slt {

const OptionSchema<InformationBoundOptions>& InformationBoundOptionsSchema() {
  using O = InformationBoundOptions;
  static const OptionSchema<O> schema =
      OptionSchema<O>()
          .Field("keyframe_interval", &O::keyframe_interval, AtLeast(1), "frames between the evaluated keyframes")
          .Field("endpoint_sigma_px", &O::endpoint_sigma_px, Positive(), "endpoint noise per coordinate (px)")
          .Field("line_gate_sigma", &O::line_gate_sigma, Positive(),
                 "a line enters a solve once its tangent's largest standard deviation (poses known) is at most this (rad, m)")
          .Field("max_iterations", &O::max_iterations, AtLeast(1), "Levenberg-Marquardt steps per solve")
          .Field("causal", &O::causal, "the pose of keyframe k from the frames up to k")
          .Field("smoother", &O::smoother, "the pose of keyframe k from the whole sequence")
          .Field("warm_start", &O::warm_start, "a causal solve starts from the previous one's estimate")
          .Field("taylor_residual", &O::taylor_residual, "restriction: Taylor's segment residual instead of the endpoint one")
          .Field("min_epipolar_angle_deg", &O::min_epipolar_angle_deg, InRange(0.0, 90.0, "[)"),
                 "restriction: lines within this of the epipolar direction at their first stereo sight are left out")
          .Field("structure_interval", &O::structure_interval, AtLeast(1),
                 "restriction: only every structure_interval-th frame (and the evaluated one) observes")
          .Field("window_frames", &O::window_frames, AtLeast(0), "restriction: a causal solve sees only its last window_frames frames (0 = all)");
  return schema;
}

void InformationBoundOptions::Check(const std::string& where, const std::string& path) const {
  InformationBoundOptionsSchema().Validate(*this, where, path);
}

namespace {

// One segment of one line in one camera of one frame.
struct Observation {
  int frame, line, camera;
};

}  // namespace

InformationBound ComputeInformationBound(const SimulatedSequence& sim, const InformationBoundOptions& options) {
  options.Check();
  ShowOnlyCeresErrors();
  const InformationBoundOptions& o = options;
  const StereoSequence& sequence = sim.sequence;
  const int frames = static_cast<int>(sequence.frames.size());
  const int lines = static_cast<int>(sim.lines.size());
  InformationBound bound;
  if (frames == 0) return bound;
  const SegmentCamera cameras[2] = {SegmentCamera::FromRig(sequence.rig, true), SegmentCamera::FromRig(sequence.rig, false)};
  PoseManifold pose_manifold;
  LineManifold line_manifold;

  // The truth: the start of every solve, and the gate's linearisation point. One buffer per kind
  // of block, in index order (Ceres orders a group's blocks by address: repeatable sums).
  std::vector<double> true_poses(static_cast<size_t>(kPoseAmbientSize) * frames);
  for (int f = 0; f < frames; ++f) PoseToParameters(sim.ground_truth[f].world_from_cam.Inverse(), &true_poses[kPoseAmbientSize * f]);
  std::vector<double> true_lines(static_cast<size_t>(kLineAmbientSize) * lines, 0.0);
  std::vector<bool> line_usable(lines, false);
  for (int i = 0; i < lines; ++i) {
    const Eigen::Vector3d d = (sim.lines[i].q - sim.lines[i].p).normalized();
    line_usable[i] = LineToParameters({sim.lines[i].p.cross(d), d}, &true_lines[kLineAmbientSize * i]);
  }

  // Restriction: lines the tracker's reference pair would not define (within the angle of the
  // epipolar direction, horizontal for a rectified rig, where the line is first seen in both
  // images) are left out.
  if (o.min_epipolar_angle_deg > 0.0) {
    std::vector<bool> decided(lines, false);
    const double sine = std::sin(o.min_epipolar_angle_deg * M_PI / 180.0);
    for (const StereoFrame& frame : sequence.frames) {
      for (const LineObservation& left : frame.left) {
        if (left.id < 0 || left.id >= lines || decided[left.id]) continue;
        const bool stereo = std::any_of(frame.right.begin(), frame.right.end(), [&](const LineObservation& r) { return r.id == left.id; });
        if (!stereo) continue;
        decided[left.id] = true;
        const Eigen::Vector2d direction = (left.segment.tail<2>() - left.segment.head<2>()).normalized();
        if (std::abs(direction.y()) < sine) line_usable[left.id] = false;
      }
    }
  }

  std::vector<Observation> observations;
  std::vector<int> frame_begin(frames + 1, 0);
  for (int f = 0; f < frames; ++f) {
    frame_begin[f] = static_cast<int>(observations.size());
    for (int c = 0; c < 2; ++c) {
      for (const LineObservation& l : c == 0 ? sequence.frames[f].left : sequence.frames[f].right) {
        if (l.id >= 0 && l.id < lines && line_usable[l.id]) observations.push_back({f, static_cast<int>(l.id), c});
      }
    }
  }
  frame_begin[frames] = static_cast<int>(observations.size());
  std::vector<TaylorSegmentCost> costs(observations.size());
  {
    size_t n = 0;
    for (int f = 0; f < frames; ++f) {
      for (int c = 0; c < 2; ++c) {
        for (const LineObservation& l : c == 0 ? sequence.frames[f].left : sequence.frames[f].right) {
          if (l.id < 0 || l.id >= lines || !line_usable[l.id]) continue;
          // Taylor's form as the reference refinement weighs it (weight 1, sigma / sqrt(2)).
          if (o.taylor_residual) costs[n++].Set(&cameras[c], l.segment, 1.0, o.endpoint_sigma_px / std::sqrt(2.0));
          else costs[n++].Set(&cameras[c], l.segment, 1.0, o.endpoint_sigma_px, SegmentResidual::kEndpoints);
        }
      }
    }
  }

  // Each observation's information on its line's tangent at the truth (the gate's).
  std::vector<Eigen::Matrix4d> line_information(observations.size(), Eigen::Matrix4d::Zero());
  for (size_t n = 0; n < observations.size(); ++n) {
    Eigen::Vector2d r;
    Eigen::Matrix<double, 2, kLineAmbientSize, Eigen::RowMajor> d_line;
    Eigen::Matrix<double, kLineAmbientSize, 4, Eigen::RowMajor> plus;
    const double* parameters[2] = {&true_poses[kPoseAmbientSize * observations[n].frame], &true_lines[kLineAmbientSize * observations[n].line]};
    double* jacobians[2] = {nullptr, d_line.data()};
    if (!costs[n].Evaluate(parameters, r.data(), jacobians)) continue;
    line_manifold.PlusJacobian(parameters[1], plus.data());
    const Eigen::Matrix<double, 2, 4> j = d_line * plus;
    line_information[n] = j.transpose() * j;
  }
  const double gate = 1.0 / (o.line_gate_sigma * o.line_gate_sigma);

  for (int f = 0; f < frames; f += o.keyframe_interval) bound.frames.push_back(f);
  if (bound.frames.back() != frames - 1) bound.frames.push_back(frames - 1);

  std::vector<double> poses = true_poses, line_parameters = true_lines;
  std::vector<bool> pose_in(frames, false), line_in(lines, false);
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_SCHUR;  // poses eliminated: the reduced system is the lines'
  solver.max_num_iterations = o.max_iterations;
  solver.num_threads = 1;
  solver.logging_type = ceres::SILENT;
  solver.function_tolerance = 1e-10;
  solver.gradient_tolerance = 1e-12;
  solver.parameter_tolerance = 1e-10;

  // The bundle adjustment over frames [first, last] (those that observe); the pose of `last`
  // is left in poses. Returns false when `last` could not take part.
  const auto solve = [&](int first, int last, bool warm) {
    const auto observes = [&](int f) { return f == last || f % o.structure_interval == 0; };
    std::vector<Eigen::Matrix4d> information(lines, Eigen::Matrix4d::Zero());
    for (int f = first; f <= last; ++f) {
      if (!observes(f)) continue;
      for (int n = frame_begin[f]; n < frame_begin[f + 1]; ++n) information[observations[n].line] += line_information[n];
    }
    std::vector<bool> determined(lines, false);
    for (int i = 0; i < lines; ++i) {
      determined[i] = line_usable[i] &&
                      Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(information[i], Eigen::EigenvaluesOnly).eigenvalues()(0) >= gate;
      if (!warm || !line_in[i]) std::copy_n(&true_lines[kLineAmbientSize * i], kLineAmbientSize, &line_parameters[kLineAmbientSize * i]);
    }
    ceres::Problem problem(BorrowingProblemOptions());
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    bool gauge_set = false;
    for (int f = first; f <= last; ++f) {
      double* pose = &poses[kPoseAmbientSize * f];
      if (!warm || !pose_in[f]) std::copy_n(&true_poses[kPoseAmbientSize * f], kPoseAmbientSize, pose);
      if (!observes(f)) continue;
      int seen = 0;
      for (int n = frame_begin[f]; n < frame_begin[f + 1]; ++n) seen += determined[observations[n].line] ? 1 : 0;
      if (seen < 4) continue;  // segments: fewer leave the pose free
      problem.AddParameterBlock(pose, kPoseAmbientSize, &pose_manifold);
      ordering->AddElementToGroup(pose, 0);
      // The gauge: the first frame (world = the first left camera), or with a window its first
      // frame at its estimate from the solves before (as a tracker holds its reference pair's).
      if (!gauge_set) problem.SetParameterBlockConstant(pose);
      gauge_set = true;
      for (int n = frame_begin[f]; n < frame_begin[f + 1]; ++n) {
        if (!determined[observations[n].line]) continue;
        double* line = &line_parameters[kLineAmbientSize * observations[n].line];
        if (!problem.HasParameterBlock(line)) {
          problem.AddParameterBlock(line, kLineAmbientSize, &line_manifold);
          ordering->AddElementToGroup(line, 1);
        }
        problem.AddResidualBlock(&costs[n], nullptr, pose, line);
      }
    }
    for (int f = 0; f < frames; ++f) pose_in[f] = problem.HasParameterBlock(&poses[kPoseAmbientSize * f]);
    for (int i = 0; i < lines; ++i) line_in[i] = problem.HasParameterBlock(&line_parameters[kLineAmbientSize * i]);
    if (!pose_in[last]) return false;
    solver.linear_solver_ordering = ordering;
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem, &summary);
    bound.iterations += static_cast<int>(summary.iterations.size()) - 1;
    return summary.IsSolutionUsable();
  };
  const auto pose_at = [&](int f) { return PoseFromParameters(&poses[kPoseAmbientSize * f]); };

  if (o.causal) {
    for (const int k : bound.frames) {
      const int first = o.window_frames > 0 ? std::max(0, k - o.window_frames + 1) : 0;
      // Frame 0 is the gauge; a frame the solve cannot place is counted (and keeps the truth).
      const bool solved = k == 0 || solve(first, k, o.warm_start);
      bound.unsolved += solved ? 0 : 1;
      bound.causal_cam_from_world.push_back(pose_at(k));
    }
  }
  if (o.smoother) {
    std::fill(pose_in.begin(), pose_in.end(), false);
    std::fill(line_in.begin(), line_in.end(), false);
    bound.unsolved += solve(0, frames - 1, false) ? 0 : 1;
    for (const int k : bound.frames) bound.smoother_cam_from_world.push_back(pose_at(k));
  }
  return bound;
}

}  // namespace slt
