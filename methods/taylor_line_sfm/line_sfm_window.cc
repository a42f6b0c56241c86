#include "methods/taylor_line_sfm/line_sfm_window.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "dataset/association.h"
#include "geometry/plucker.h"
#include "methods/pose_tracker.h"
#include "optim/ceres_logging.h"

namespace slt {
namespace {

// Union-find over frame indices, for the connected group of the newest frame.
int Root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// The depth at which the ray through pixel x of `camera` meets the line (given in that camera's
// frame): X = z r on the line means z (r x d) = n. Exact for a line triangulated from this
// segment (the ray lies in its back-projected plane); NaN or infinite for a ray along the line.
double DepthOnLine(const PinholeCamera& camera, const Eigen::Vector2d& x, const PlueckerLine& line) {
  const Eigen::Vector3d r_cross_d = Homogeneous(camera.PixelToNormalized(x)).cross(line.direction);
  return r_cross_d.dot(line.moment) / r_cross_d.squaredNorm();
}

}  // namespace

void CollectWindowObservations(const std::vector<LineObservation>& image, std::vector<LineObservation>* scratch,
                               std::vector<WindowObservation>* out) {
  out->clear();
  for (const LineObservation& o : SortedById(image, scratch)) {
    if (UsableSegment(o.segment)) out->push_back({o.id, o.segment});
  }
}

LineSfmWindow::LineSfmWindow(const TaylorLineSfmOptions& options) : options_(options) {
  options_.Check();
  ShowOnlyCeresErrors();
  min_plane_sine_ = std::sin(options_.min_plane_angle_deg * M_PI / 180.0);
  if (options_.loss == SegmentLoss::kHuber) {
    robust_loss_ = std::make_unique<ceres::HuberLoss>(options_.loss_scale);
  } else if (options_.loss == SegmentLoss::kCauchy) {
    robust_loss_ = std::make_unique<ceres::CauchyLoss>(options_.loss_scale);
  }
  solver_options_.linear_solver_type =
      options_.linear_solver == WindowLinearSolver::kSparseSchur ? ceres::SPARSE_SCHUR : ceres::DENSE_SCHUR;
  solver_options_.max_num_iterations = options_.max_iterations;
  solver_options_.function_tolerance = options_.function_tolerance;
  solver_options_.gradient_tolerance = options_.gradient_tolerance;
  solver_options_.parameter_tolerance = options_.parameter_tolerance;
  solver_options_.num_threads = options_.threads;
  solver_options_.logging_type = ceres::SILENT;
  solver_options_.minimizer_progress_to_stdout = false;
}

void LineSfmWindow::Reset(const StereoRig& rig) {
  rig.Check();
  rig_ = rig;
  cameras_[0] = SegmentCamera::FromRig(rig, true);
  cameras_[1] = SegmentCamera::FromRig(rig, false);
  frames_.clear();
  lines_.clear();
}

void LineSfmWindow::AddFrame(const Rigid3d& cam_from_world, std::vector<WindowObservation> left,
                             std::vector<WindowObservation> right) {
  FrameState& frame = frames_.emplace_back();
  PoseToParameters(cam_from_world, frame.pose);
  frame.images[0] = std::move(left);
  frame.images[1] = std::move(right);
  if (options_.window_frames > 0) {
    while (static_cast<int>(frames_.size()) > options_.window_frames) frames_.pop_front();
  }
  // Lines no remaining segment observes go (rejected segments count: a line is kept while it is
  // in view).
  for (auto& [id, line] : lines_) line.observing_frames = 0;
  for (const FrameState& f : frames_) {
    for (const std::vector<WindowObservation>& image : f.images) {
      for (const WindowObservation& o : image) {
        if (auto it = lines_.find(o.id); it != lines_.end()) ++it->second.observing_frames;
      }
    }
  }
  for (auto it = lines_.begin(); it != lines_.end();) {
    it = it->second.observing_frames == 0 ? lines_.erase(it) : std::next(it);
  }
}

template <typename Visit>
void LineSfmWindow::ForEachLine(const FrameState& f, Visit visit) {
  ++visit_;
  for (const std::vector<WindowObservation>& image : f.images) {
    for (const WindowObservation& o : image) {
      if (o.outlier) continue;
      const auto it = lines_.find(o.id);
      if (it == lines_.end() || it->second.visit == visit_) continue;
      it->second.visit = visit_;
      visit(it->second);
    }
  }
}

int LineSfmWindow::KnownLinesInNewest() {
  int count = 0;
  if (!frames_.empty()) ForEachLine(frames_.back(), [&](LineState&) { ++count; });
  return count;
}

int LineSfmWindow::KnownLinesInBothImagesOfNewest() {
  if (frames_.empty()) return 0;
  // Mark the lines of the left image, then count the marked ones the right image sees (each
  // once: counted lines get another mark).
  const int mark = ++visit_;
  for (const WindowObservation& o : frames_.back().images[0]) {
    const auto it = lines_.find(o.id);
    if (!o.outlier && it != lines_.end()) it->second.visit = mark;
  }
  const int counted = ++visit_;
  int count = 0;
  for (const WindowObservation& o : frames_.back().images[1]) {
    const auto it = lines_.find(o.id);
    if (o.outlier || it == lines_.end() || it->second.visit != mark) continue;
    it->second.visit = counted;
    ++count;
  }
  return count;
}

int LineSfmWindow::LinesAgreeingInNewest(double rms_sigma) {
  if (frames_.empty()) return 0;
  const FrameState& newest = frames_.back();
  // |r|^2 = (rms / sigma)^2 with unit weight (taylor_segment_cost.h).
  const double threshold = rms_sigma * rms_sigma;
  // visit: this call's mark for a line seen so far; a disagreeing segment marks it `failed`.
  const int seen = ++visit_;
  const int failed = ++visit_;
  for (int camera = 0; camera < 2; ++camera) {
    for (const WindowObservation& o : newest.images[camera]) {
      const auto it = lines_.find(o.id);
      if (o.outlier || it == lines_.end()) continue;
      LineState& line = it->second;
      if (line.visit != seen && line.visit != failed) line.visit = seen;
      TaylorSegmentCost cost;
      cost.Set(&cameras_[camera], o.segment, 1.0, options_.sigma_px);
      const double* parameters[] = {newest.pose, line.parameters};
      Eigen::Vector2d r;
      if (!cost.Evaluate(parameters, r.data(), nullptr) || !(r.squaredNorm() <= threshold)) line.visit = failed;
    }
  }
  int agreeing = 0;
  for (const auto& [id, line] : lines_) agreeing += line.visit == seen;
  return agreeing;
}

Rigid3d LineSfmWindow::Pose(int age) const { return PoseFromParameters(frames_[frames_.size() - 1 - age].pose); }

void LineSfmWindow::SetNewestPose(const Rigid3d& cam_from_world) { PoseToParameters(cam_from_world, frames_.back().pose); }

PlueckerLine LineSfmWindow::Line(std::int64_t id) const { return LineFromParameters(lines_.at(id).parameters); }

bool LineSfmWindow::SelectProblem(WindowSolveReport* report) {
  const int n = static_cast<int>(frames_.size());
  for (FrameState& f : frames_) f.included = true;
  std::vector<int> parent(n);
  for (bool changed = true; changed;) {
    changed = false;
    for (auto& [id, line] : lines_) line.observing_frames = 0;
    for (const FrameState& f : frames_) {
      if (f.included) ForEachLine(f, [](LineState& line) { ++line.observing_frames; });
    }
    for (auto& [id, line] : lines_) line.eligible = line.observing_frames >= options_.min_observation_frames;
    for (FrameState& f : frames_) {
      if (!f.included) continue;
      f.eligible_lines = 0;
      ForEachLine(f, [&](LineState& line) { f.eligible_lines += line.eligible; });
      if (f.eligible_lines < 2) {
        f.included = false;
        changed = true;
      }
    }
    if (changed) continue;
    // Only the group of frames linked to the newest one through shared lines.
    std::iota(parent.begin(), parent.end(), 0);
    for (auto& [id, line] : lines_) line.observing_frames = -1;  // reused: last frame seen in
    for (int k = 0; k < n; ++k) {
      if (!frames_[k].included) continue;
      ForEachLine(frames_[k], [&](LineState& line) {
        if (!line.eligible) return;
        if (line.observing_frames >= 0) parent[Root(parent, line.observing_frames)] = Root(parent, k);
        line.observing_frames = k;
      });
    }
    const int newest_root = Root(parent, n - 1);
    for (int k = 0; k < n; ++k) {
      if (frames_[k].included && Root(parent, k) != newest_root) {
        frames_[k].included = false;
        changed = true;
      }
    }
    // Eligibility is recounted over the remaining frames on the next pass.
  }
  const FrameState& newest = frames_.back();
  ForEachLine(newest, [&](LineState& line) { report->newest_lines_too_few_observations += !line.eligible; });
  const int included = static_cast<int>(std::count_if(frames_.begin(), frames_.end(), [](const FrameState& f) { return f.included; }));
  report->newest_in_problem = newest.included && included >= 2;
  if (!report->newest_in_problem) return false;
  report->frames = included;
  ForEachLine(newest, [&](LineState& line) { report->newest_lines += line.eligible; });
  for (const std::vector<WindowObservation>& image : newest.images) {
    for (const WindowObservation& o : image) {
      const auto it = lines_.find(o.id);
      if (!o.outlier && it != lines_.end() && it->second.eligible) ++report->newest_observations;
    }
  }
  return true;
}

WindowSolveReport LineSfmWindow::Solve() {
  WindowSolveReport report = SolveOnce();
  if (!report.solved || !(options_.outlier_rms_sigma > 0.0)) return report;
  const int rejected = RejectOutliers(&report);
  if (rejected == 0) return report;
  // Once more without the rejected segments (and the dropped lines).
  WindowSolveReport again = SolveOnce();
  again.iterations += report.iterations;
  again.initial_cost = report.initial_cost;
  again.rejected_observations = report.rejected_observations;
  again.dropped_lines = report.dropped_lines;
  again.solves = 2;
  return again;
}

int LineSfmWindow::RejectOutliers(WindowSolveReport* report) {
  // |r|^2 / w = (rms / sigma)^2 (taylor_segment_cost.h).
  const double threshold = options_.outlier_rms_sigma * options_.outlier_rms_sigma;
  for (auto& [id, line] : lines_) line.kept = line.rejected = 0;
  int rejected = 0;
  for (size_t u = 0; u < residuals_.size(); ++u) {
    const ResidualRef& ref = residuals_[u];
    const double* parameters[] = {workspace_.data() + ref.pose_offset, workspace_.data() + ref.line->offset};
    Eigen::Vector2d r;
    const bool ok = costs_[u].Evaluate(parameters, r.data(), nullptr);
    if (ok && r.squaredNorm() <= threshold * ref.weight) {
      ++ref.line->kept;
    } else {
      ref.observation->outlier = true;
      ++ref.line->rejected;
      ++rejected;
    }
  }
  report->rejected_observations += rejected;
  // A line that most of its segments disagree with is more likely wrong than they are (a stereo
  // pair with an outlier made it): it goes, its segments are judged again, and it is
  // triangulated anew from its next stereo pair.
  for (auto it = lines_.begin(); it != lines_.end();) {
    if (it->second.rejected <= it->second.kept) {
      ++it;
      continue;
    }
    for (FrameState& f : frames_) {
      for (std::vector<WindowObservation>& image : f.images) {
        for (WindowObservation& o : image) {
          if (o.id == it->first) o.outlier = false;
        }
      }
    }
    it = lines_.erase(it);
    ++report->dropped_lines;
  }
  return rejected;
}

WindowSolveReport LineSfmWindow::SolveOnce() {
  WindowSolveReport report;
  residuals_.clear();
  if (frames_.empty() || !SelectProblem(&report)) return report;

  // The problem's parameters are copies in one array, poses first, then lines in the order the
  // residuals meet them: Ceres orders parameter blocks within an elimination group by address,
  // so this makes the solve independent of where the map's nodes happen to be allocated (and
  // a failed solve leaves the window as it was).
  size_t size = 0;
  for (FrameState& f : frames_) {
    f.offset = f.included ? static_cast<int>(size) : -1;
    if (f.included) size += kPoseAmbientSize;
  }
  for (auto& [id, line] : lines_) line.offset = -1;
  for (const FrameState& f : frames_) {
    if (!f.included) continue;
    ForEachLine(f, [&](LineState& line) {
      if (!line.eligible || line.offset >= 0) return;
      line.offset = static_cast<int>(size);
      size += kLineAmbientSize;
    });
  }
  workspace_.resize(size);
  for (const FrameState& f : frames_) {
    if (f.included) std::copy(f.pose, f.pose + kPoseAmbientSize, workspace_.data() + f.offset);
  }
  for (const auto& [id, line] : lines_) {
    if (line.offset >= 0) std::copy(line.parameters, line.parameters + kLineAmbientSize, workspace_.data() + line.offset);
  }

  ceres::Problem problem(BorrowingProblemOptions());
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();  // lines eliminated first

  size_t used = 0;
  bool gauge_fixed = false;
  for (FrameState& f : frames_) {
    if (!f.included) continue;
    double* pose = workspace_.data() + f.offset;
    problem.AddParameterBlock(pose, kPoseAmbientSize, gauge_fixed ? &pose_manifold_ : nullptr);
    if (!gauge_fixed) problem.SetParameterBlockConstant(pose);
    gauge_fixed = true;
    ordering->AddElementToGroup(pose, 1);
    for (int camera = 0; camera < 2; ++camera) {
      for (WindowObservation& o : f.images[camera]) {
        const auto it = lines_.find(o.id);
        if (o.outlier || it == lines_.end() || !it->second.eligible) continue;
        double* line = workspace_.data() + it->second.offset;
        if (!problem.HasParameterBlock(line)) {
          problem.AddParameterBlock(line, kLineAmbientSize, &line_manifold_);
          ordering->AddElementToGroup(line, 0);
          ++report.lines;
        }
        if (used == costs_.size()) {
          costs_.emplace_back();
          losses_.emplace_back();
        }
        const double weight = options_.length_weighting ? SegmentLength(o.segment) : 1.0;
        costs_[used].Set(&cameras_[camera], o.segment, weight, options_.sigma_px);
        ceres::LossFunction* loss = nullptr;
        if (robust_loss_) {
          losses_[used].Set(robust_loss_.get(), weight);
          loss = &losses_[used];
        }
        problem.AddResidualBlock(&costs_[used], loss, pose, line);
        residuals_.push_back({&o, &it->second, f.offset, weight});
        ++used;
      }
    }
  }
  report.residuals = static_cast<int>(used);

  solver_options_.linear_solver_ordering = ordering;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options_, &problem, &summary);
  solver_options_.linear_solver_ordering.reset();
  report.termination = summary.termination_type;
  // summary.iterations starts with the initial point (counted as a successful step).
  report.iterations = std::max(0, static_cast<int>(summary.iterations.size()) - 1);
  report.initial_cost = summary.initial_cost;
  report.final_cost = summary.final_cost;
  report.solves = 1;
  report.solved = summary.IsSolutionUsable() && Eigen::Map<const Eigen::VectorXd>(workspace_.data(), size).allFinite();
  if (!report.solved) return report;
  for (FrameState& f : frames_) {
    if (f.included) std::copy_n(workspace_.data() + f.offset, kPoseAmbientSize, f.pose);
  }
  for (auto& [id, line] : lines_) {
    if (line.offset >= 0) std::copy_n(workspace_.data() + line.offset, kLineAmbientSize, line.parameters);
  }
  return report;
}

bool LineSfmWindow::InFrontOfBothCameras(const PlueckerLine& in_left, const Segment2d& left,
                                         const Segment2d& right) const {
  const PlueckerLine in_right = TransformPluecker(rig_.right_from_left, in_left);
  return DepthOnLine(rig_.left, left.head<2>(), in_left) > 0.0 && DepthOnLine(rig_.left, left.tail<2>(), in_left) > 0.0 &&
         DepthOnLine(rig_.right, right.head<2>(), in_right) > 0.0 &&
         DepthOnLine(rig_.right, right.tail<2>(), in_right) > 0.0;
}

TriangulationReport LineSfmWindow::TriangulateNewLines() {
  TriangulationReport report;
  if (frames_.empty()) return report;
  const FrameState& newest = frames_.back();
  const Rigid3d world_from_cam = Pose(0).Inverse();
  JoinById(newest.images[0], newest.images[1], [&](size_t l, size_t r) {
    const WindowObservation& left = newest.images[0][l];
    const WindowObservation& right = newest.images[1][r];
    if (HasLine(left.id)) return;
    double plane_sine = 0.0;
    const PlueckerLine in_cam = StereoPairLine(
        rig_.right_from_left, NormalizedLineFromPixelLine(rig_.left, LineFromSegment(left.segment)),
        NormalizedLineFromPixelLine(rig_.right, LineFromSegment(right.segment)), nullptr, nullptr, &plane_sine);
    LineState line;
    if (!(plane_sine >= min_plane_sine_) || !InFrontOfBothCameras(in_cam, left.segment, right.segment) ||
        !LineToParameters(TransformPluecker(world_from_cam, in_cam), line.parameters)) {
      ++report.degenerate;
      return;
    }
    lines_.emplace(left.id, line);
    ++report.triangulated;
  });
  return report;
}

}  // namespace slt
