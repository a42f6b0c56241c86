#include "methods/trifocal_line_ekf/reference_refinement.h"

#include <ceres/numeric_diff_cost_function.h>
#include <ceres/problem.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/chi_square.h"
#include "geometry/se3.h"
#include "optim/ceres_logging.h"
#include "optim/line_pose_marginals.h"

namespace slt {
namespace {

// Up to this many keyframes in a solve the lines' covariances come through the poses' Schur
// complement (AddKeyframeAndSolve), beyond it through the lines' reduced information.
constexpr int kMaxPoseSchurKeyframes = 64;

// The prior of a carried line: r = S Minus(L, L0), S^T S the inverse of its covariance.
struct LinePrior {
  bool operator()(const double* line, double* residual) const {
    Eigen::Vector4d d;
    LineManifold().Minus(line, prior, d.data());
    Eigen::Map<Eigen::Vector4d> out(residual);
    out = sqrt_information * d;
    return true;
  }
  double prior[kLineAmbientSize];
  Eigen::Matrix4d sqrt_information;
};

}  // namespace

const OptionSchema<ReferenceRefinementOptions>& ReferenceRefinementOptionsSchema() {
  using O = ReferenceRefinementOptions;
  static const OptionSchema<O> schema =
      OptionSchema<O>()
          .Field("enabled", &O::enabled,
                 "refine the reference lines jointly with keyframe poses (direction reference_to_current only)")
          .Field("keyframe_interval", &O::keyframe_interval, AtLeast(1), "measured frames between keyframes (at least)")
          .Field("keyframe_min_distance_m", &O::keyframe_min_distance_m, AtLeast(0.0),
                 "a keyframe also needs the camera this far from the previous keyframe (0 = by count only)")
          .Field("max_keyframes", &O::max_keyframes, AtLeast(1), "keyframes kept in the refinement window")
          .Field("max_iterations", &O::max_iterations, AtLeast(1), "Levenberg-Marquardt steps per refinement")
          .Field("huber_sigma", &O::huber_sigma, Positive(), "Huber threshold of the segment residual (sigmas)")
          .Field("segment_residual", &O::segment_residual,
                 {{SegmentResidual::kTaylor, "taylor"}, {SegmentResidual::kEndpoints, "endpoints"}},
                 "segment residual: Taylor's integral or the endpoints' distances")
          .Field("move_pose", &O::move_pose, "the current pose follows the refined keyframe pose")
          .Field("pose_covariance", &O::pose_covariance,
                 {{PoseCovarianceSource::kFilter, "filter"}, {PoseCovarianceSource::kSolve, "solve"},
                  {PoseCovarianceSource::kCover, "cover"}, {PoseCovarianceSource::kReportCover, "report_cover"},
                  {PoseCovarianceSource::kReportPlacement, "report_placement"}},
                 "after a solve, the pose covariance: the filter's, the solve's marginal of the current frame, the filter's "
                 "widened to cover it, only the reported one widened so, or the reported one with the reference "
                 "pair's placement relative to its lines added")
          .Field("endpoint_sigma_px", &O::endpoint_sigma_px, AtLeast(0.0),
                 "endpoint noise the solve weighs by, px (0 = the measurement's endpoint_sigma_px)")
          .Field("carry_over", &O::carry_over,
                 "a new reference pair starts from the refined lines it shares with the previous one (as priors)")
          .Field("map_max_age", &O::map_max_age, AtLeast(0),
                 "with carry_over, also the refined lines of this many reference pairs before the previous one")
          .Field("map_association_px", &O::map_association_px, AtLeast(0.0),
                 "with carry_over, a new reference line takes the kept line whose projection lies within this of "
                 "its endpoints in both images, px (0 = by id only)")
          .Check("map_max_age",
                 [](const O& o) { return o.map_max_age > 0 && !o.carry_over ? "needs carry_over" : ""; })
          .Check("map_association_px",
                 [](const O& o) { return o.map_association_px > 0.0 && !o.carry_over ? "needs carry_over" : ""; })
          .Field("min_triangulation_angle_deg", &O::min_triangulation_angle_deg, InRange(0.0, 90.0, "[)"),
                 "lines the reference pair does not define: triangulated from a keyframe at this plane angle (0 = never, the default)")
          .Field("triangulated_max_sigma_m", &O::triangulated_max_sigma_m, AtLeast(0.0),
                 "a triangulated line reaches the filter once its position's largest standard deviation is at most this (0 = no bound)")
          .Field("triangulated_gate_probability", &O::triangulated_gate_probability, InRange(0.0, 1.0, "[)"),
                 "a triangulated line reaches the filter once its residuals pass the chi-square test at this probability (0 = no test)");
  return schema;
}

void ReferenceRefinementOptions::Check(const std::string& where, const std::string& path) const {
  ReferenceRefinementOptionsSchema().Validate(*this, where, path);
}

ReferenceRefiner::ReferenceRefiner(const ReferenceRefinementOptions& options, double endpoint_sigma_px)
    : options_(options),
      // Taylor's residual (weight 1) is (h1^2 + h1 h2 + h2^2) / (3 sigma^2) over the endpoint
      // distances h1, h2; with sigma^2 = sigma_e^2 / 2 its information on the line's offset
      // (h1 = h2) is that of two independent endpoints, 2 / sigma_e^2, and on its tilt
      // (h1 = -h2) a third of it: a little conservative.
      // The endpoint form, (h1^2 + h2^2) / sigma_e^2, has the same information on the offset and
      // three times Taylor's on the tilt.
      sigma_px_(options.segment_residual == SegmentResidual::kTaylor ? endpoint_sigma_px / std::sqrt(2.0) : endpoint_sigma_px),
      min_triangulation_sine_(std::sin(options.min_triangulation_angle_deg * M_PI / 180.0)),
      loss_(std::make_unique<ceres::HuberLoss>(options.huber_sigma)) {
  options_.Check();
  solver_options_.linear_solver_type = ceres::DENSE_SCHUR;
  solver_options_.max_num_iterations = options_.max_iterations;
  solver_options_.num_threads = 1;
  solver_options_.logging_type = ceres::SILENT;
  solver_options_.minimizer_progress_to_stdout = false;
  ShowOnlyCeresErrors();
}

void ReferenceRefiner::Reset(const StereoRig& rig) {
  cameras_[0] = SegmentCamera::FromRig(rig, true);
  cameras_[1] = SegmentCamera::FromRig(rig, false);
  StartReference(0);
}

void ReferenceRefiner::StartReference(int lines) {
  lines_.clear();
  lines_.resize(lines);
  keyframes_.clear();
  frames_since_keyframe_ = 0;
}

void ReferenceRefiner::SetLine(int index, const PlueckerLine& line, bool usable, const Segment2d& left,
                               const Segment2d& right, const Eigen::Vector3d& left_line) {
  LineState& s = lines_[index];
  s.left_line = left_line;
  s.usable = usable && LineToParameters(line, s.parameters);
  s.refined = false;
  s.triangulated = false;
  s.held_back = false;
  s.prior_cost.reset();
  s.left = left;
  s.right = right;
}

void ReferenceRefiner::SetCarriedLine(int index, const PlueckerLine& line, const Eigen::Matrix4d& covariance) {
  LineState& s = lines_[index];
  auto* prior = new LinePrior;
  Eigen::LLT<Eigen::Matrix4d> llt(covariance);
  if (!LineToParameters(line, s.parameters) || !LineToParameters(line, prior->prior) || llt.info() != Eigen::Success) {
    delete prior;
    return;
  }
  // S = L^-1 for C = L L^T: |S d|^2 = d^T C^-1 d.
  prior->sqrt_information = llt.matrixL().solve(Eigen::Matrix4d::Identity());
  s.prior_sqrt_information = prior->sqrt_information;
  s.prior_cost.reset(new ceres::NumericDiffCostFunction<LinePrior, ceres::CENTRAL, 4, kLineAmbientSize>(prior));
  s.usable = true;
  s.refined = true;
  s.covariance = covariance;
}

bool ReferenceRefiner::CountFrame(const Rigid3d& cam_from_ref) {
  if (++frames_since_keyframe_ < options_.keyframe_interval) return false;
  if (options_.keyframe_min_distance_m > 0.0) {
    const Eigen::Vector3d last = keyframes_.empty() ? Eigen::Vector3d::Zero() : PoseFromParameters(keyframes_.back().pose).Center();
    if ((cam_from_ref.Center() - last).norm() < options_.keyframe_min_distance_m) return false;
  }
  frames_since_keyframe_ = 0;
  return true;
}

Eigen::Matrix<double, 6, 4> ReferenceRefiner::TangentBasis(int index) const {
  return LineTangentBasis(lines_[index].parameters);
}

bool ReferenceRefiner::AddKeyframeAndSolve(const Rigid3d& cam_from_ref, const std::vector<Observation>& observations,
                                           Rigid3d* newest_cam_from_ref) {
  newest_covariance_valid_ = false;
  placement_valid_ = false;
  keyframes_.emplace_back();
  PoseToParameters(cam_from_ref, keyframes_.back().pose);
  keyframes_.back().observations = observations;
  if (options_.min_triangulation_angle_deg > 0.0) {
    // The back-projected planes of the reference's left segment and this keyframe's
    // (StereoPairLine with the keyframe as the second camera).
    for (const Observation& o : observations) {
      LineState& l = lines_[o.line];
      if (l.usable) continue;
      double sine = 0.0;
      const PlueckerLine line = StereoPairLine(cam_from_ref, l.left_line, o.left_line, nullptr, nullptr, &sine);
      if (sine >= min_triangulation_sine_) l.usable = l.triangulated = LineToParameters(line, l.parameters);
    }
  }
  // Over the window: drop the keyframe nearest its successor (camera centres; never the
  // newest), so that the window keeps the widest spread of viewpoints -- the parallax that
  // defines the lines -- rather than only the latest frames.
  while (static_cast<int>(keyframes_.size()) > options_.max_keyframes) {
    size_t drop = 0;
    double nearest = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k + 1 < keyframes_.size(); ++k) {
      const double d = (PoseFromParameters(keyframes_[k].pose).Center() - PoseFromParameters(keyframes_[k + 1].pose).Center()).norm();
      if (d < nearest) {
        nearest = d;
        drop = k;
      }
    }
    keyframes_.erase(keyframes_.begin() + static_cast<std::ptrdiff_t>(drop));
  }

  // Lines enter with at least one keyframe observation; keyframes with at least two such lines
  // (one line leaves a pose direction free).
  for (LineState& l : lines_) l.observations = 0;
  for (const Keyframe& k : keyframes_) {
    for (const Observation& o : k.observations) {
      lines_[o.line].observations += lines_[o.line].usable && !lines_[o.line].triangulated ? 1 : 0;
    }
  }
  // The solve's pose blocks, in one buffer: the reference pair's pose, then the keyframes' in
  // window order. Ceres orders the blocks of each elimination group by address (a std::set of
  // pointers), and that order decides the order of its floating-point sums: blocks wherever the
  // heap put them (the deque's chunks) made runs of the same sequence differ. The lines are
  // elements of one vector, in index order, for the same reason.
  pose_parameters_.assign(kPoseAmbientSize * (keyframes_.size() + 1), 0.0);
  PoseToParameters(Rigid3d(), pose_parameters_.data());
  for (size_t k = 0; k < keyframes_.size(); ++k) {
    std::copy_n(keyframes_[k].pose, kPoseAmbientSize, pose_parameters_.data() + kPoseAmbientSize * (k + 1));
  }
  auto pose_of = [&](size_t k) { return pose_parameters_.data() + kPoseAmbientSize * (k + 1); };
  double* const reference_pose = pose_parameters_.data();
  ceres::Problem problem(BorrowingProblemOptions());
  // The Schur elimination's first group: the lines (a reduced system over the poses), or the
  // poses when the window holds more keyframes than kMaxPoseSchurKeyframes (a reduced system
  // over the lines, which grows with their number instead; equal up to rounding).
  const bool many_poses = static_cast<int>(keyframes_.size()) > kMaxPoseSchurKeyframes;
  const int line_group = many_poses ? 1 : 0;
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  problem.AddParameterBlock(reference_pose, kPoseAmbientSize);
  problem.SetParameterBlockConstant(reference_pose);
  ordering->AddElementToGroup(reference_pose, 1);
  size_t used = 0;
  residuals_.clear();
  auto add = [&](double* pose, int line, const Segment2d& left, const Segment2d& right) {
    double* parameters = lines_[line].parameters;
    if (!problem.HasParameterBlock(parameters)) {
      problem.AddParameterBlock(parameters, kLineAmbientSize, &line_manifold_);
      ordering->AddElementToGroup(parameters, line_group);
    }
    for (int c = 0; c < 2; ++c) {
      if (used == costs_.size()) costs_.emplace_back();
      costs_[used].Set(&cameras_[c], c == 0 ? left : right, 1.0, sigma_px_, options_.segment_residual);
      problem.AddResidualBlock(&costs_[used], loss_.get(), pose, parameters);
      residuals_.push_back({pose, line});
      ++used;
    }
  };
  bool newest_in = false;
  for (size_t k = 0; k < keyframes_.size(); ++k) {
    const std::vector<Observation>& seen_lines = keyframes_[k].observations;
    const int seen = static_cast<int>(std::count_if(seen_lines.begin(), seen_lines.end(),
                                                    [&](const Observation& o) { return lines_[o.line].observations > 0; }));
    if (seen < 2) continue;
    problem.AddParameterBlock(pose_of(k), kPoseAmbientSize, &pose_manifold_);
    ordering->AddElementToGroup(pose_of(k), 1 - line_group);
    for (const Observation& o : seen_lines) {
      if (lines_[o.line].usable && !lines_[o.line].triangulated) add(pose_of(k), o.line, o.left, o.right);
    }
    newest_in = k + 1 == keyframes_.size();
  }
  if (!newest_in) return false;
  for (int i = 0; i < static_cast<int>(lines_.size()); ++i) {
    LineState& l = lines_[i];
    if (!problem.HasParameterBlock(l.parameters)) continue;
    add(reference_pose, i, l.left, l.right);
    if (l.prior_cost) problem.AddResidualBlock(l.prior_cost.get(), nullptr, l.parameters);
  }

  // Keep the start: a failed solve leaves everything as it was (the keyframes' poses are
  // copied back only after a usable solve).
  std::vector<double> saved;
  for (const LineState& l : lines_) saved.insert(saved.end(), l.parameters, l.parameters + kLineAmbientSize);
  solver_options_.linear_solver_ordering = ordering;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options_, &problem, &summary);
  solver_options_.linear_solver_ordering.reset();
  ++solves_;
  bool finite = summary.IsSolutionUsable() &&
                Eigen::Map<const Eigen::VectorXd>(pose_parameters_.data(), static_cast<Eigen::Index>(pose_parameters_.size())).allFinite();
  for (const LineState& l : lines_) finite = finite && Eigen::Map<const Eigen::Matrix<double, 6, 1>>(l.parameters).allFinite();
  if (!finite) {
    const double* s = saved.data();
    for (LineState& l : lines_) {
      std::copy_n(s, kLineAmbientSize, l.parameters);
      s += kLineAmbientSize;
    }
    return false;
  }
  for (size_t k = 0; k < keyframes_.size(); ++k) std::copy_n(pose_of(k), kPoseAmbientSize, keyframes_[k].pose);

  // Each line's covariance: its block of the inverse of the problem's Gauss-Newton information
  // J^T J (whitened residuals, tangent coordinates; the Huber weights left out), i.e. the
  // line's uncertainty given the reference pair, marginalised over the keyframe poses. (The
  // inverse of the line's own block alone, poses held fixed, was far too confident: NEES in
  // the thousands on the room loop.) With the information [A B; B^T D] (A block-diagonal over
  // the lines, D the poses') and S = D - B^T A^-1 B, the block of line i is
  //     A_i^-1 + A_i^-1 B_i S^-1 B_i^T A_i^-1.
  std::vector<int> line_offset(lines_.size(), -1);
  int line_rows = 0;
  for (size_t i = 0; i < lines_.size(); ++i) {
    if (problem.HasParameterBlock(lines_[i].parameters)) {
      line_offset[i] = line_rows;
      line_rows += 4;
    }
  }
  std::vector<std::pair<const double*, int>> pose_offset;
  int pose_rows = 0;
  for (size_t k = 0; k < keyframes_.size(); ++k) {
    if (problem.HasParameterBlock(pose_of(k))) {
      pose_offset.emplace_back(pose_of(k), pose_rows);
      pose_rows += 6;
    }
  }
  auto offset_of_pose = [&](const double* pose) {
    for (const auto& [p, o] : pose_offset) {
      if (p == pose) return o;
    }
    return -1;  // the reference pair: fixed
  };
  // Two ways to the same blocks, equal up to rounding: through the poses' Schur complement S
  // (dense over the poses, cubic in their number), which the triangulated lines also need
  // (their covariance adds the poses'), or through the lines' reduced information
  // A - B D^-1 B^T (D block-diagonal: a residual sees one pose), whose inverse's diagonal
  // blocks are the lines' marginal covariances, cubic in the lines. The poses' form is kept
  // up to kMaxPoseSchurKeyframes keyframes so that earlier results reproduce to the bit.
  const int pose_count = pose_rows / 6;
  // The newest keyframe's marginal only when a pose covariance is taken from the solve.
  const bool wants_newest = options_.pose_covariance != PoseCovarianceSource::kFilter &&
                            options_.pose_covariance != PoseCovarianceSource::kReportPlacement;
  const bool wants_placement = options_.pose_covariance == PoseCovarianceSource::kReportPlacement;
  const int newest_offset = offset_of_pose(pose_of(keyframes_.size() - 1));  // >= 0: newest_in
  const bool pose_schur = options_.min_triangulation_angle_deg > 0.0 || !many_poses;
  Eigen::MatrixXd a_blocks = Eigen::MatrixXd::Zero(line_rows, 4);  // A_i stacked
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(line_rows, pose_rows);
  std::vector<Matrix6d> d_blocks(static_cast<size_t>(pose_count), Matrix6d::Zero());
  Eigen::Vector2d residual;
  Eigen::Matrix<double, 2, kPoseAmbientSize, Eigen::RowMajor> d_pose;
  Eigen::Matrix<double, 2, kLineAmbientSize, Eigen::RowMajor> d_line;
  Eigen::Matrix<double, kPoseAmbientSize, 6, Eigen::RowMajor> pose_plus;
  Matrix6d reference_information = Matrix6d::Zero();
  for (size_t k = 0; k < residuals_.size(); ++k) {
    const int line = residuals_[k].line;
    const double* parameters[2] = {residuals_[k].pose, lines_[line].parameters};
    double* jacobians[2] = {d_pose.data(), d_line.data()};
    if (!costs_[k].Evaluate(parameters, residual.data(), jacobians)) continue;
    const Eigen::Matrix<double, 2, 4> j_line = d_line * TangentBasis(line);
    const int l = line_offset[line];
    a_blocks.block<4, 4>(l, 0).noalias() += j_line.transpose() * j_line;
    const int p = offset_of_pose(residuals_[k].pose);
    // The reference pair's block is held fixed; its information is the placement's.
    const bool reference = p < 0 && wants_placement && residuals_[k].pose == reference_pose;
    if (p < 0 && !reference) continue;
    pose_manifold_.PlusJacobian(residuals_[k].pose, pose_plus.data());
    const Eigen::Matrix<double, 2, 6> j_pose = d_pose * pose_plus;
    if (reference) {
      reference_information.noalias() += j_pose.transpose() * j_pose;
      continue;
    }
    d_blocks[static_cast<size_t>(p / 6)].noalias() += j_pose.transpose() * j_pose;
    b.block<4, 6>(l, p).noalias() += j_line.transpose() * j_pose;
  }
  Eigen::MatrixXd a_inverse_b(pose_schur ? line_rows : 0, pose_rows);  // the poses' form only
  std::vector<Eigen::Matrix4d> a_inverse(lines_.size());
  std::vector<bool> ok(lines_.size(), false);
  Eigen::MatrixXd schur;
  if (pose_schur) {
    schur = Eigen::MatrixXd::Zero(pose_rows, pose_rows);
    for (int k = 0; k < pose_count; ++k) schur.block<6, 6>(6 * k, 6 * k) = d_blocks[static_cast<size_t>(k)];
  }
  for (size_t i = 0; i < lines_.size(); ++i) {
    const int l = line_offset[i];
    if (l < 0) continue;
    if (lines_[i].prior_cost) {
      // Its prior's information (at the prior's tangent; the step since is small).
      a_blocks.block<4, 4>(l, 0).noalias() += lines_[i].prior_sqrt_information.transpose() * lines_[i].prior_sqrt_information;
    }
    const Eigen::LDLT<Eigen::Matrix4d> ldlt(a_blocks.block<4, 4>(l, 0));
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) {
      if (pose_schur) a_inverse_b.middleRows<4>(l).setZero();
      continue;
    }
    ok[i] = true;
    if (!pose_schur) continue;
    a_inverse[i] = ldlt.solve(Eigen::Matrix4d::Identity());
    a_inverse_b.middleRows<4>(l).noalias() = a_inverse[i] * b.middleRows<4>(l);
    schur.noalias() -= b.middleRows<4>(l).transpose() * a_inverse_b.middleRows<4>(l);
  }
  bool poses_determined = false;
  Eigen::MatrixXd schur_inverse;  // the keyframe poses' marginal covariance
  if (pose_schur) {
    const Eigen::LDLT<Eigen::MatrixXd> schur_ldlt(schur);
    poses_determined = pose_rows > 0 && schur_ldlt.info() == Eigen::Success && schur_ldlt.isPositive();
    if (poses_determined) {
      schur_inverse = schur_ldlt.solve(Eigen::MatrixXd::Identity(pose_rows, pose_rows));
      if (wants_newest) newest_covariance_ = schur_inverse.block<6, 6>(newest_offset, newest_offset);
      for (size_t i = 0; i < lines_.size(); ++i) {
        const int l = line_offset[i];
        if (l < 0 || !ok[i]) continue;
        const auto x = a_inverse_b.middleRows<4>(l);
        lines_[i].covariance = a_inverse[i] + x * schur_inverse * x.transpose();
        lines_[i].refined = lines_[i].covariance.allFinite() && lines_[i].covariance.diagonal().minCoeff() > 0.0;
      }
    }
  } else if (pose_rows > 0) {
    // The lines with a positive-definite own block, as the poses' form keeps them
    // (optim/line_pose_marginals.h).
    std::vector<int> kept;
    for (size_t i = 0; i < lines_.size(); ++i) {
      if (line_offset[i] >= 0 && ok[i]) kept.push_back(static_cast<int>(i));
    }
    std::vector<Eigen::Matrix4d> kept_a(kept.size());
    Eigen::MatrixXd kept_b(4 * static_cast<Eigen::Index>(kept.size()), pose_rows);
    for (size_t j = 0; j < kept.size(); ++j) {
      kept_a[j] = a_blocks.block<4, 4>(line_offset[kept[j]], 0);
      kept_b.middleRows<4>(4 * static_cast<Eigen::Index>(j)) = b.middleRows<4>(line_offset[kept[j]]);
    }
    std::vector<Eigen::Matrix4d> covariances;
    poses_determined = LineMarginalCovariances(kept_a, kept_b, d_blocks, &covariances, newest_offset / 6,
                                               wants_newest ? &newest_covariance_ : nullptr);
    if (poses_determined) {
      for (size_t j = 0; j < kept.size(); ++j) {
        LineState& l = lines_[static_cast<size_t>(kept[j])];
        l.covariance = covariances[j];
        l.refined = l.covariance.allFinite() && l.covariance.diagonal().minCoeff() > 0.0;
      }
    }
  }
  newest_covariance_valid_ = wants_newest && poses_determined && newest_covariance_.allFinite();
  if (wants_placement) {
    const Eigen::LDLT<Matrix6d> ldlt(reference_information);
    if (reference_information.allFinite() && ldlt.info() == Eigen::Success && ldlt.isPositive()) {
      placement_covariance_ = ldlt.solve(Matrix6d::Identity());
      placement_valid_ = placement_covariance_.allFinite() && placement_covariance_.diagonal().minCoeff() > 0.0;
    }
  }
  if (poses_determined) RefineTriangulatedLines(pose_of, offset_of_pose, schur_inverse, problem, &used);
  *newest_cam_from_ref = PoseFromParameters(keyframes_.back().pose);
  return true;
}

template <typename PoseOf, typename OffsetOfPose>
void ReferenceRefiner::RefineTriangulatedLines(const PoseOf& pose_of, const OffsetOfPose& offset_of_pose,
                                               const Eigen::MatrixXd& pose_covariance, const ceres::Problem& solved,
                                               size_t* used) {
  // The lines triangulated from temporal parallax stay out of the joint solve (in it, their
  // small-parallax errors bent the keyframe poses and through them the stereo lines: room loop,
  // docs/long_sequences.md). Each is refined alone against the solved poses, held fixed; its
  // covariance adds the poses' uncertainty, A^-1 + A^-1 B P B^T A^-1 (A its information, B the
  // line-pose block, P the poses' marginal covariance), and it reaches the filter only through
  // the consistency gate (triangulated_max_sigma_m, triangulated_gate_probability).
  ceres::Solver::Options options = solver_options_;
  options.linear_solver_type = ceres::DENSE_QR;
  const int pose_rows = static_cast<int>(pose_covariance.rows());
  Eigen::Vector2d residual;
  Eigen::Matrix<double, 2, kPoseAmbientSize, Eigen::RowMajor> d_pose;
  Eigen::Matrix<double, 2, kLineAmbientSize, Eigen::RowMajor> d_line;
  Eigen::Matrix<double, kPoseAmbientSize, 6, Eigen::RowMajor> pose_plus;
  Eigen::MatrixXd b(4, pose_rows);
  for (int i = 0; i < static_cast<int>(lines_.size()); ++i) {
    LineState& l = lines_[i];
    l.held_back = false;
    if (!l.triangulated || l.prior_cost) continue;
    ceres::Problem problem(BorrowingProblemOptions());
    problem.AddParameterBlock(l.parameters, kLineAmbientSize, &line_manifold_);
    const size_t first = *used;
    auto add = [&](double* pose, const Segment2d& left, const Segment2d& right) {
      if (!problem.HasParameterBlock(pose)) {
        problem.AddParameterBlock(pose, kPoseAmbientSize, &pose_manifold_);
        problem.SetParameterBlockConstant(pose);
      }
      for (int c = 0; c < 2; ++c) {
        if (*used == costs_.size()) costs_.emplace_back();
        costs_[*used].Set(&cameras_[c], c == 0 ? left : right, 1.0, sigma_px_, options_.segment_residual);
        problem.AddResidualBlock(&costs_[*used], loss_.get(), pose, l.parameters);
        residuals_.push_back({pose, i});
        ++*used;
      }
    };
    for (size_t k = 0; k < keyframes_.size(); ++k) {
      if (!solved.HasParameterBlock(pose_of(k))) continue;
      for (const Observation& o : keyframes_[k].observations) {
        if (o.line == i) add(pose_of(k), o.left, o.right);
      }
    }
    if (*used == first) continue;  // not seen in the window
    add(pose_parameters_.data(), l.left, l.right);
    double saved[kLineAmbientSize];
    std::copy_n(l.parameters, kLineAmbientSize, saved);
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    if (!summary.IsSolutionUsable() || !Eigen::Map<const Eigen::Matrix<double, 6, 1>>(l.parameters).allFinite()) {
      std::copy_n(saved, kLineAmbientSize, l.parameters);
      l.held_back = l.refined;
      l.refined = false;
      continue;
    }
    Eigen::Matrix4d a = Eigen::Matrix4d::Zero();
    b.setZero();
    double sum = 0.0;
    int segments = 0;
    for (size_t r = first; r < *used; ++r) {
      const double* parameters[2] = {residuals_[r].pose, l.parameters};
      double* jacobians[2] = {d_pose.data(), d_line.data()};
      if (!costs_[r].Evaluate(parameters, residual.data(), jacobians)) continue;
      sum += residual.squaredNorm();
      ++segments;
      const Eigen::Matrix<double, 2, 4> j_line = d_line * TangentBasis(i);
      a.noalias() += j_line.transpose() * j_line;
      const int p = offset_of_pose(residuals_[r].pose);
      if (p < 0) continue;
      pose_manifold_.PlusJacobian(residuals_[r].pose, pose_plus.data());
      b.middleCols<6>(p).noalias() += j_line.transpose() * (d_pose * pose_plus);
    }
    const Eigen::LDLT<Eigen::Matrix4d> ldlt(a);
    bool pass = ldlt.info() == Eigen::Success && ldlt.isPositive();
    if (pass) {
      const Eigen::Matrix4d a_inverse = ldlt.solve(Eigen::Matrix4d::Identity());
      const Eigen::Matrix<double, 4, Eigen::Dynamic> x = a_inverse * b;
      l.covariance = a_inverse + x * pose_covariance * x.transpose();
      const double sigma_m = std::sqrt(std::max(
          0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(l.covariance.bottomRightCorner<2, 2>()).eigenvalues()(1)));
      const int dof = 2 * segments - 4;
      const double max_sigma_m = options_.triangulated_max_sigma_m;
      const double probability = options_.triangulated_gate_probability;
      pass = l.covariance.allFinite() && l.covariance.diagonal().minCoeff() > 0.0 &&
             (max_sigma_m == 0.0 || sigma_m <= max_sigma_m) &&
             (probability == 0.0 || (dof >= 1 && sum <= ChiSquareQuantile(probability, dof)));
    }
    l.held_back = !pass && l.refined;
    l.refined = pass;
  }
}

}  // namespace slt
