#include "methods/elqursh_three_line/elqursh_three_line.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "common/json_reader.h"
#include "geometry/se3.h"
#include "geometry/trifocal.h"
#include "methods/elqursh_three_line/candidate_triplets.h"
#include "methods/elqursh_three_line/three_line_solver.h"
#include "methods/stereo_ekf/least_squares.h"
#include "optim/ransac.h"

namespace slt {
namespace {

double Radians(double degrees) { return degrees * M_PI / 180.0; }

// A line matched between the reference and the current pair whose reference pair defines a 3-D
// line in front of the reference camera.
struct MatchedLine {
  int feature = 0;                  // index in the LineTransferModel
  Eigen::Vector3d reference_left;   // unit normalised lines, for the rotation
  Eigen::Vector3d current_left;
  StereoLineConstraint constraint;  // for the translation
};

// The RANSAC estimator (optim/ransac.h): data are the matched lines, samples are candidate
// triplets, models are cam_from_ref.
class ThreeLineEstimator : public FixedSampleSize<3> {
 public:
  using Model = Rigid3d;

  ThreeLineEstimator(const ElqurshThreeLineOptions& options, const StereoRig& rig, const LineTransferModel& model,
                     const std::vector<MatchedLine>& lines, const std::vector<Eigen::Vector3d>& directions,
                     const PrimitiveConfigurationTolerances& tolerances, CandidateTriplets& candidates,
                     std::vector<WeightedFeature>* refine_features, std::vector<int>* refine_indices)
      : options_(options),
        rig_(rig),
        model_(model),
        lines_(lines),
        directions_(directions),
        tolerances_(tolerances),
        candidates_(candidates),
        min_sine_(std::sin(Radians(options.min_view_angle_deg))),
        min_trace_(1.0 + 2.0 * std::cos(Radians(options.max_rotation_deg))),
        threshold_(options.inlier_threshold_px * options.inlier_threshold_px),
        refine_features_(refine_features),
        refine_indices_(refine_indices) {}

  int NumData() const { return static_cast<int>(lines_.size()); }
  // The next candidate triplet (candidate_triplets.h), or none: every one of a short list was
  // drawn.
  int DrawSample(std::mt19937_64& rng, int* sample) const {
    LineTriplet triplet;
    if (!candidates_.Next(rng, &triplet)) return 0;
    std::copy(triplet.begin(), triplet.end(), sample);
    return 3;
  }

  void MinimalSolve(const int* sample, int count, std::vector<Rigid3d>* models) const {
    LineTriplet roles;
    if (count != 3 || !AssignPrimitiveRoles({sample[0], sample[1], sample[2]}, directions_, tolerances_, &roles)) return;
    const MatchedLine &p1 = lines_[roles[0]], &p2 = lines_[roles[1]], &o = lines_[roles[2]];
    RotationCandidates rotations;
    if (RotationFromPrimitiveConfiguration({p1.reference_left, p2.reference_left, o.reference_left},
                                           {p1.current_left, p2.current_left, o.current_left}, min_sine_,
                                           &rotations) != PrimitiveConfigurationStatus::kValid) {
      return;
    }
    const StereoLineConstraint constraints[3] = {p1.constraint, p2.constraint, o.constraint};
    for (int i = 0; i < rotations.count; ++i) {
      if (!SmallEnough(rotations.b_from_a[i])) continue;
      Rigid3d pose(rotations.b_from_a[i], Eigen::Vector3d::Zero());
      if (!TranslationFromStereoLines(pose.rotation, rig_.right_from_left, constraints, 3, kMinEigenvalueRatio,
                                      &pose.translation)) {
        continue;
      }
      // The sample over-determines the pose (12 endpoint distances, 6 unknowns): a sign
      // candidate that does not explain its own three lines is not scored on the others.
      if (ExplainsSample(roles, pose)) models->push_back(pose);
    }
  }

  // Mean squared endpoint distance (px^2) of the line's reference 3-D line imaged at `model`
  // from its four observed endpoints in the current pair.
  bool Cost(int datum, const Rigid3d& model, double* cost) const {
    Eigen::Vector4d distances;
    if (!model_.EndpointDistances(lines_[datum].feature, model, &distances)) return false;
    *cost = 0.25 * distances.squaredNorm();
    return std::isfinite(*cost);
  }
  double Threshold(int) const { return threshold_; }
  bool SmallEnough(const Eigen::Matrix3d& rotation) const { return rotation.trace() >= min_trace_; }
  bool Agrees(int datum, const Rigid3d& model) const {
    double cost;
    return Cost(datum, model, &cost) && cost < threshold_;
  }
  bool ExplainsSample(const LineTriplet& sample, const Rigid3d& model) const {
    return Agrees(sample[0], model) && Agrees(sample[1], model) && Agrees(sample[2], model);
  }

  bool LocalOptimize(const std::vector<int>& inliers, Rigid3d* model) const {
    refine_indices_->clear();
    for (int d : inliers) refine_indices_->push_back(lines_[d].feature);
    Matrix6d information;
    Rigid3d pose = *model;
    if (!RefinePose(model_, *refine_features_, refine_indices_->data(), static_cast<int>(refine_indices_->size()),
                    options_.refine_iterations, &pose, &information)) {
      return false;
    }
    if (!SmallEnough(pose.rotation)) return false;
    *model = pose;
    return true;
  }

 private:
  // The translation's rows must fix all three directions (three_line_solver.h): rejects sets
  // of parallel lines (rank 2) to rounding.
  static constexpr double kMinEigenvalueRatio = 1e-9;

  const ElqurshThreeLineOptions& options_;
  const StereoRig& rig_;
  const LineTransferModel& model_;
  const std::vector<MatchedLine>& lines_;
  const std::vector<Eigen::Vector3d>& directions_;
  const PrimitiveConfigurationTolerances& tolerances_;
  CandidateTriplets& candidates_;
  const double min_sine_;
  const double min_trace_;  // trace(R) >= 1 + 2 cos(max_rotation): the rotation angle is within the bound
  const double threshold_;
  std::vector<WeightedFeature>* refine_features_;
  std::vector<int>* refine_indices_;
};

LineTransferOptions MeasurementOptions(const ElqurshThreeLineOptions& o) {
  LineTransferOptions m;
  m.direction = TransferDirection::kReferenceToCurrent;
  m.residual = LineResidual::kEndpointDistance;
  m.epipolar = o.epipolar;
  return m;
}

class ElqurshThreeLineTracker final : public PoseTracker {
 public:
  explicit ElqurshThreeLineTracker(const ElqurshThreeLineOptions& options)
      : options_(options), model_(MeasurementOptions(options)) {
    tolerances_.max_parallel_sine = std::sin(Radians(options.parallel_tolerance_deg));
    tolerances_.max_orthogonal_cosine = std::sin(Radians(options.orthogonal_tolerance_deg));
  }

  void Reset(const StereoRig& rig) override {
    rig.Check();
    rig_ = rig;
    model_.Reset(rig);
    ransac_.Reset(options_.ransac.seed);
    started_ = false;
    velocity_.setZero();
  }

  TrackerOutput Track(const StereoFrame& frame) override;
  nlohmann::json Options() const override;

 private:
  // Makes `frame` the reference pair at the pose `ref_from_world`.
  void SetReference(const StereoFrame& frame, const Rigid3d& ref_from_world) {
    reference_features_ = model_.SetReference(frame);
    ref_from_world_ = ref_from_world;
    lost_frames_ = 0;
  }
  // Fills lines_, directions_ and refine_features_ from the model's matches.
  void CollectMatchedLines();

  ElqurshThreeLineOptions options_;
  LineTransferModel model_;
  PrimitiveConfigurationTolerances tolerances_;
  Ransac<Rigid3d> ransac_;
  StereoRig rig_;
  bool started_ = false;
  Rigid3d ref_from_world_;
  Rigid3d cam_from_world_;
  int lost_frames_ = 0;  // lost frames measured against the current reference
  // The last measured motion per frame, log(cam_t_from_cam_t-1) (geometry/se3.h): the
  // constant-velocity prediction of a lost frame.
  Vector6d velocity_ = Vector6d::Zero();
  int reference_features_ = 0;  // stereo lines of the reference pair

  // Per-frame workspace, kept to avoid allocation.
  std::vector<MatchedLine> lines_;
  std::vector<Eigen::Vector3d> directions_;
  CandidateTriplets candidates_;
  std::vector<WeightedFeature> refine_features_;
  std::vector<int> refine_indices_;
  RansacResult<Rigid3d> result_;
};

void ElqurshThreeLineTracker::CollectMatchedLines() {
  lines_.clear();
  directions_.clear();
  const int n = model_.NumFeatures();
  refine_features_.resize(n);
  for (int i = 0; i < n; ++i) {
    const LineTransferModel::StereoLine& ref = model_.ReferenceObservation(i);
    if (ref.degenerate) continue;
    const LineTransferModel::StereoLine& cur = model_.CurrentObservation(i);
    const PlueckerLine& line = model_.ReferenceLine3d(i);
    // The point of the 3-D line on the ray of the reference left segment's middle: where that
    // ray meets the plane of the reference right line (E^T [l'; 0], geometry/plucker.h).
    const Eigen::Vector2d middle =
        rig_.left.PixelToNormalized(0.5 * (ref.left.segment.head<2>() + ref.left.segment.tail<2>()));
    Eigen::Vector4d right_plane;
    right_plane << rig_.right_from_left.rotation.transpose() * ref.right.line,
        rig_.right_from_left.translation.dot(ref.right.line);
    const Eigen::Vector4d x = IntersectRayWithPlane(Homogeneous(middle), right_plane);
    const Eigen::Vector3d point = x.head<3>() / x(3);
    const Eigen::Vector3d point_in_right = rig_.right_from_left * point;
    if (!point.allFinite() || point.z() <= 0.0 || point_in_right.z() <= 0.0) continue;
    MatchedLine m;
    m.feature = i;
    m.reference_left = ref.left.line;
    m.current_left = cur.left.line;
    // Rows weighted so that their residuals are image distances in normalised coordinates at
    // the reference depth (three_line_solver.h).
    m.constraint.point_in_a = point;
    m.constraint.left_normal = cur.left.line / (cur.left.line.head<2>().norm() * point.z());
    m.constraint.right_normal = cur.right.line / (cur.right.line.head<2>().norm() * point_in_right.z());
    lines_.push_back(m);
    directions_.push_back(line.direction.normalized());
    // Gauss-Newton on endpoint distances in px, unweighted (RefinePose whitens with L = I).
    WeightedFeature& f = refine_features_[i];
    f.block.measured_rows = FeatureBlock::kAllRows;
    f.sqrt_covariance.setIdentity();
  }
}

TrackerOutput ElqurshThreeLineTracker::Track(const StereoFrame& frame) {
  TrackerOutput out;
  if (!started_) {
    started_ = true;
    cam_from_world_ = Rigid3d();
    SetReference(frame, cam_from_world_);
    out.status = TrackingStatus::kNewReference;
    out.reason = StatusReason::kFirstFrame;
    out.features_available = reference_features_;
    return out;
  }
  model_.SetCurrent(frame);
  CollectMatchedLines();
  const int available = static_cast<int>(lines_.size());
  out.features_available = available;
  // The reference's lines not matched in both images of this pair, and the matched ones without
  // a usable triangulation (degenerate or behind the rig).
  out.features_unmatched = std::max(0, reference_features_ - model_.NumFeatures());
  out.features_degenerate = model_.NumFeatures() - available;
  candidates_.Build(directions_, tolerances_);
  bool accepted = false;
  if (!candidates_.empty()) {
    const ThreeLineEstimator estimator(options_, rig_, model_, lines_, directions_, tolerances_, candidates_,
                                       &refine_features_, &refine_indices_);
    candidates_.StartDraws(options_.ransac.max_iterations);
    ransac_.Run(estimator, options_.ransac, {}, &result_);
    const int needed = std::max(options_.min_inliers,
                                static_cast<int>(std::ceil(options_.min_inlier_fraction * available)));
    const int consensus = static_cast<int>(result_.inliers.size());
    accepted = result_.success && consensus >= needed && result_.model.AllFinite();
    if (accepted) out.features_used = consensus;
  }
  out.features_outside_gate = available - out.features_used;
  if (accepted) {
    // The motion since the reference, spread over the frames it spans (the lost ones between).
    velocity_ = LogSE3(result_.model) / static_cast<double>(lost_frames_ + 1);
    cam_from_world_ = result_.model * ref_from_world_;
    out.status = TrackingStatus::kTracking;
    SetReference(frame, cam_from_world_);
  } else {
    // Lost: the pose is the constant-velocity prediction from the last measured motion, its
    // velocity multiplied by lost_velocity_decay on every lost frame (0 = hold the pose). The
    // reference stays for a while (the next frame that finds a configuration measures the
    // motion of the lost ones too), unless this frame offers more: enough lines of its own
    // while too few of the reference's are still seen, a reference whose matched lines hold no
    // candidate configuration at all (the candidates come from the reference's 3-D directions,
    // and a later frame sees at most the reference lines this one sees: it cannot do better),
    // or a reference that has failed for max_lost_frames frames (its configurations do not
    // work). The new reference takes the predicted pose.
    out.status = TrackingStatus::kLost;
    // Too few lines, no triplet that may be a primitive configuration (the rotation is not
    // measured), or a consensus too small.
    out.reason = available < options_.min_inliers ? StatusReason::kFewMeasurable
                 : candidates_.empty()              ? StatusReason::kUnconstrained
                                                    : StatusReason::kFewAgree;
    ++lost_frames_;
    cam_from_world_ = CoastAtConstantVelocity(options_.lost, &velocity_, cam_from_world_);
    const bool has_lines = model_.CurrentStereoFeatures() >= options_.min_inliers;
    if (has_lines && (out.reason != StatusReason::kFewAgree || lost_frames_ > options_.max_lost_frames)) {
      SetReference(frame, cam_from_world_);
    }
  }
  out.cam_from_world = cam_from_world_;
  return out;
}

nlohmann::json ElqurshThreeLineTracker::Options() const { return ElqurshThreeLineOptionsSchema().ToJson(options_); }

std::unique_ptr<PoseTracker> Create(const nlohmann::json& json, const std::string& where) {
  JsonReader reader(json, where);
  ElqurshThreeLineOptions options;
  ElqurshThreeLineOptionsSchema().Read(reader, &options);
  reader.RejectUnknownKeys();
  return std::make_unique<ElqurshThreeLineTracker>(options);
}

}  // namespace

const OptionSchema<ElqurshThreeLineOptions>& ElqurshThreeLineOptionsSchema() {
  using O = ElqurshThreeLineOptions;
  static const OptionSchema<O> schema =
      OptionSchema<O>()
          .Field("parallel_tolerance_deg", &O::parallel_tolerance_deg, InRange(0.0, 45.0, "()"),
                 "candidate parallel lines: stereo 3-D directions within this angle")
          .Field("orthogonal_tolerance_deg", &O::orthogonal_tolerance_deg, InRange(0.0, 45.0, "()"),
                 "candidate orthogonal line: within this angle of orthogonal to both")
          .Field("min_view_angle_deg", &O::min_view_angle_deg, InRange(0.0, 45.0, "()"),
                 "a configuration's view is degenerate below this angle (three_line_solver.h)")
          .Field("max_rotation_deg", &O::max_rotation_deg, InRange(0.0, 180.0, "(]"),
                 "larger rotations between a frame and its reference are rejected")
          .Field("inlier_threshold_px", &O::inlier_threshold_px, Positive().Finite(),
                 "a line agrees with a pose below this RMS endpoint distance (px)")
          .Flat(&O::ransac, RansacOptionsSchema())
          .Field("refine_iterations", &O::refine_iterations, InRange(0, 50), "Gauss-Newton iterations on the consensus")
          .Field("min_inliers", &O::min_inliers, AtLeast(3).Note("a configuration has three lines"),
                 "smallest consensus accepted (lines)")
          .Field("min_inlier_fraction", &O::min_inlier_fraction, InRange(0.0, 1.0),
                 "smallest consensus accepted (fraction of the measurable lines)")
          .Field("max_lost_frames", &O::max_lost_frames, AtLeast(0).Note("0 = always the previous frame"),
                 "lost frames against one reference before the current frame replaces it")
          .Flat(&O::lost, LostFrameOptionsSchema())
          .Flat(&O::epipolar, EpipolarLineOptionsSchema());
  return schema;
}

void ElqurshThreeLineOptions::Check(const std::string& where) const {
  ElqurshThreeLineOptionsSchema().Validate(*this, where, "");
}

TrackerInfo ElqurshThreeLineInfo() {
  TrackerInfo info;
  info.name = "elqursh_three_line";
  info.description = "Three-line relative pose with RANSAC, chained frame to frame (Elqursh & Elgammal, CVPR 2011)";
  info.create = Create;
  info.list_options = [] { return ElqurshThreeLineOptionsSchema().Docs(); };
  info.minimum_lines = 3;
  info.needs_primitive_configurations = true;
  return info;
}

}  // namespace slt
