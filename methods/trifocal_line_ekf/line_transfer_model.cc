#include "methods/trifocal_line_ekf/line_transfer_model.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "dataset/association.h"
#include "geometry/trifocal.h"
#include "methods/pose_tracker.h"
#include "optim/line_sfm_manifolds.h"

namespace slt {
namespace {

// Endpoint pairing of a line placed by its endpoints: below this difference (px) between the
// epipolar distances of the two pairings, the segments' directions decide (geometry/stereo_point.h).
constexpr double kEndpointPairingAmbiguityPx = 1.0;
// Endpoints placed nearer than this to the reference camera leave the line unmeasured (m).
constexpr double kMinPlacedDepthM = 0.05;

// The floor of a propagated R on the theta rows of the (theta, lambda) residual (rad).
constexpr double kCovarianceFloorRad = 1e-4;

// The options that use the reference lines' covariance need it: it is propagated from the
// endpoints in the reference_to_current direction only.
std::string NeedsPropagatedReferenceToCurrent(bool used, const LineTransferOptions& o) {
  return used && (o.direction != TransferDirection::kReferenceToCurrent || o.noise != MeasurementNoise::kPropagated)
             ? std::string("needs direction reference_to_current and noise propagated")
             : std::string();
}

}  // namespace

const OptionSchema<EpipolarLineOptions>& EpipolarLineOptionsSchema() {
  static const OptionSchema<EpipolarLineOptions> schema = OptionSchema<EpipolarLineOptions>().Field(
      "min_epipolar_angle_deg", &EpipolarLineOptions::min_epipolar_angle_deg, InRange(0.0, 90.0, "[)"),
      "lines this close to the epipolar direction are not measured");
  return schema;
}

const OptionSchema<LineTransferOptions>& LineTransferOptionsSchema() {
  using O = LineTransferOptions;
  static const OptionSchema<O> schema =
      OptionSchema<O>()
          .Field("direction", &O::direction,
                 {{TransferDirection::kCurrentToReference, "current_to_reference"},
                  {TransferDirection::kReferenceToCurrent, "reference_to_current"}},
                 "transfer direction; current_to_reference is the paper's (eq. 16)")
          .Field("residual", &O::residual,
                 {{LineResidual::kEndpointDistance, "endpoint_distance"}, {LineResidual::kThetaLambda, "theta_lambda"}},
                 "endpoint distances (px) or the paper's (theta, lambda) (eq. 8-9)")
          .Field("noise", &O::noise, MeasurementNoiseNames(),
                 "R propagated from the endpoint noise, or the paper's fixed diagonal R")
          .Field("endpoint_sigma_px", &O::endpoint_sigma_px, Positive(), "endpoint noise per coordinate (px), propagated R")
          .Field("covariance_floor_px", &O::covariance_floor_px, Positive(), "floor added to a propagated R (px)")
          .Field("fixed_sigma_px", &O::fixed_sigma_px, Positive(), "fixed R: distances and lambda (px)")
          .Field("fixed_sigma_rad", &O::fixed_sigma_rad, Positive(), "fixed R: theta (rad)")
          .Flat(&O::epipolar, EpipolarLineOptionsSchema())
          .Field("min_epipolar_extent_px", &O::min_epipolar_extent_px, AtLeast(0.0),
                 "lines spanning fewer pixels across the epipolar lines are not measured (0 = off)")
          .Field("endpoint_placement_sigma_px", &O::endpoint_placement_sigma_px, AtLeast(0.0),
                 "lines in an epipolar plane placed by their endpoints, sigma along the segment (px; 0 = off)")
          .Field("min_plane_angle_deg", &O::min_plane_angle_deg, InRange(0.0, 90.0, "[)"),
                 "current_to_reference: transfers through planes this close are not measured (Sec. 4)")
          .Child("refinement", &O::refinement, ReferenceRefinementOptionsSchema(),
                 "joint refinement of the reference lines with keyframe poses (issue 16)")
          .Field("consider_structure", &O::consider_structure,
                 "the reference lines' error as consider parameters of the filter (Schmidt-Kalman)")
          .Check("consider_structure",
                 [](const O& o) { return NeedsPropagatedReferenceToCurrent(o.consider_structure, o); })
          .Check("endpoint_placement_sigma_px",
                 [](const O& o) { return NeedsPropagatedReferenceToCurrent(o.endpoint_placement_sigma_px > 0.0, o); })
          .Check("refinement.enabled",
                 [](const O& o) { return NeedsPropagatedReferenceToCurrent(o.refinement.enabled, o); });
  return schema;
}

void LineTransferOptions::Check(const std::string& where, const std::string& path) const {
  LineTransferOptionsSchema().Validate(*this, where, path);
}

void ReadLineTransferOptions(JsonReader& r, LineTransferOptions* o) { LineTransferOptionsSchema().Read(r, o); }

nlohmann::json LineTransferOptionsToJson(const LineTransferOptions& o) { return LineTransferOptionsSchema().ToJson(o); }

LineTransferModel::LineTransferModel(const LineTransferOptions& options) : options_(options) {
  options_.Check();
  paper_direction_ = options_.direction == TransferDirection::kCurrentToReference;
  distance_residual_ = options_.residual == LineResidual::kEndpointDistance;
  propagated_noise_ = options_.noise == MeasurementNoise::kPropagated;
  min_epipolar_sine_ = std::sin(options_.epipolar.min_epipolar_angle_deg * M_PI / 180.0);
  min_plane_sine_ = std::sin(options_.min_plane_angle_deg * M_PI / 180.0);
  // Residual units per scalar: [px, px, px, px] or [rad, px, rad, px].
  Eigen::Vector4d fixed_sigma, floor;
  if (distance_residual_) {
    fixed_sigma.setConstant(options_.fixed_sigma_px);
    floor.setConstant(options_.covariance_floor_px);
  } else {
    fixed_sigma << options_.fixed_sigma_rad, options_.fixed_sigma_px, options_.fixed_sigma_rad, options_.fixed_sigma_px;
    floor << kCovarianceFloorRad, options_.covariance_floor_px, kCovarianceFloorRad, options_.covariance_floor_px;
  }
  fixed_covariance_ = fixed_sigma.array().square().matrix().asDiagonal();
  covariance_floor_ = floor.array().square();
  if (options_.refinement.enabled) {
    const double sigma_px = options_.refinement.endpoint_sigma_px > 0.0 ? options_.refinement.endpoint_sigma_px
                                                                         : options_.endpoint_sigma_px;
    refiner_ = std::make_unique<ReferenceRefiner>(options_.refinement, sigma_px);
    line_map_ = ReferenceLineMap(options_.refinement.map_max_age);
  }
}

const Rigid3d& LineTransferModel::RightFromRef(const Rigid3d& cam_from_ref) const {
  // Every feature of a frame is evaluated at the same pose: compose once per pose.
  if (cam_from_ref.rotation != cached_cam_from_ref_.rotation ||
      cam_from_ref.translation != cached_cam_from_ref_.translation) {
    cached_cam_from_ref_ = cam_from_ref;
    cached_right_from_ref_ = rig_.right_from_left * cam_from_ref;
  }
  return cached_right_from_ref_;
}

void LineTransferModel::Reset(const StereoRig& rig) {
  rig_ = rig;
  point_geometry_ = StereoPointGeometry(rig);
  right_adjoint_ = Adjoint(rig.right_from_left);
  left_epipole_ = rig.right_from_left.Center();
  cached_cam_from_ref_ = Rigid3d();
  cached_right_from_ref_ = rig.right_from_left;
  left_pixel_from_normalized_ = PixelFromNormalizedLineMatrix(rig.left);
  right_pixel_from_normalized_ = PixelFromNormalizedLineMatrix(rig.right);
  reference_.clear();
  current_.clear();
  matches_.clear();
  current_stereo_ = 0;
  line_map_.Reset(rig);
  if (refiner_) refiner_->Reset(rig);
}

bool LineTransferModel::MakeSegment(const Segment2d& segment, const PinholeCamera& camera,
                                    ObservedSegment* out) const {
  if (!UsableSegment(segment)) return false;
  Eigen::Matrix<double, 3, 4> d_pixel_line;
  const Eigen::Vector3d pixel_line = LineFromSegment(segment, &d_pixel_line);
  // K^T: the normalised line (eq. 6-7).
  Eigen::Matrix3d kt;
  kt << camera.fx, 0.0, 0.0, 0.0, camera.fy, 0.0, camera.cx, camera.cy, 1.0;
  const Eigen::Vector3d line = kt * pixel_line;
  const double inv_norm = 1.0 / line.norm();
  out->segment = segment;
  out->line = line * inv_norm;
  // Scaling the Jacobian by the same factor (without the projection onto the unit sphere) is
  // exact here: every residual is invariant to the positive scale of its input lines.
  out->line_d_segment = (kt * d_pixel_line) * inv_norm;
  return true;
}

int LineTransferModel::CountUsable(const std::vector<StereoLine>& lines) {
  return static_cast<int>(std::count_if(lines.begin(), lines.end(), [](const StereoLine& l) { return !l.degenerate; }));
}

bool LineTransferModel::NearEpipolar(const ObservedSegment& left) const {
  // The epipolar line through the segment's middle (normalised coordinates) joins it to the
  // epipole; compare the two lines' normals.
  const Eigen::Vector2d middle = rig_.left.PixelToNormalized(0.5 * (left.segment.head<2>() + left.segment.tail<2>()));
  const Eigen::Vector3d epipolar = Homogeneous(middle).cross(left_epipole_);
  const Eigen::Vector2d a = left.line.head<2>(), b = epipolar.head<2>();
  const double denominator = a.norm() * b.norm();
  if (!(denominator > 0.0)) return true;
  const double sine = std::abs(a.x() * b.y() - a.y() * b.x()) / denominator;
  const double length_px = (left.segment.head<2>() - left.segment.tail<2>()).norm();
  return sine < min_epipolar_sine_ || sine * length_px < options_.min_epipolar_extent_px;
}

void LineTransferModel::CollectStereoLines(const StereoFrame& frame, std::vector<StereoLine>* out) {
  const std::vector<LineObservation>& left = SortedById(frame.left, &left_sorted_);
  const std::vector<LineObservation>& right = SortedById(frame.right, &right_sorted_);
  out->clear();
  JoinById(left, right, [&](size_t l, size_t r) {
    StereoLine line;
    line.id = left[l].id;
    if (MakeSegment(left[l].segment, rig_.left, &line.left) && MakeSegment(right[r].segment, rig_.right, &line.right)) {
      line.degenerate = NearEpipolar(line.left);
      out->push_back(line);
    }
  });
}

int LineTransferModel::SetReference(const StereoFrame& frame) {
  // The refined lines of the reference pairs so far (this one's and, with
  // refinement.map_max_age, earlier ones'), moved into the new pair's frame when this frame's
  // pose is known (RefineStructure ran on it), to be carried into it as priors
  // (reference_line_map.h).
  const bool carry = refiner_ && options_.refinement.carry_over;
  if (carry) {
    line_map_.Age();
    for (size_t i = 0; i < reference_.size(); ++i) {
      const ReferenceLine& line = reference_lines_[i];
      if (line.refined) line_map_.Keep(reference_[i].id, {line.line, line.line_d_tangent, line.tangent_covariance});
    }
    if (last_pose_valid_) {
      line_map_.Move(last_cam_from_ref_);
    } else {
      line_map_.Clear();
    }
  }
  CollectStereoLines(frame, &reference_);
  reference_lines_.resize(reference_.size());
  int placed = 0;
  for (size_t i = 0; i < reference_.size(); ++i) {
    const StereoLine& ref = reference_[i];
    ReferenceLine& out = reference_lines_[i];
    Matrix63d d_left, d_right;
    out.line = StereoPairLine(rig_.right_from_left, ref.left.line, ref.right.line, &d_left, &d_right);
    out.line_d_left_segment = d_left * ref.left.line_d_segment;
    out.line_d_right_segment = d_right * ref.right.line_d_segment;
    out.refined = false;
    ++out.version;
    if (options_.endpoint_placement_sigma_px > 0.0 && ref.degenerate) placed += PlaceByEndpoints(static_cast<int>(i));
  }
  if (refiner_) {
    refiner_->StartReference(static_cast<int>(reference_.size()));
    for (size_t i = 0; i < reference_.size(); ++i) {
      refiner_->SetLine(static_cast<int>(i), reference_lines_[i].line, !reference_[i].degenerate,
                        reference_[i].left.segment, reference_[i].right.segment, reference_[i].left.line);
    }
  }
  if (carry && line_map_.size() > 0) {
    // A line of the new pair is a map line by its id, else (map_association_px) by its
    // projection, among the map lines whose ids the new pair does not hold (reference_ is
    // sorted by id).
    const auto held = [this](std::int64_t id) { return ContainsId(reference_, id); };
    const double association_px = options_.refinement.map_association_px;
    for (size_t i = 0; i < reference_.size(); ++i) {
      std::int64_t id = reference_[i].id;
      const ReferenceLineMap::Line* carried = line_map_.Find(id);
      if (carried == nullptr && association_px > 0.0 &&
          line_map_.FindByProjection(reference_[i].left.segment, reference_[i].right.segment, association_px, held,
                                     &id)) {
        carried = line_map_.Find(id);
      }
      if (carried == nullptr) continue;
      const int index = static_cast<int>(i);
      refiner_->SetCarriedLine(index, carried->line, carried->tangent_covariance);
      if (refiner_->Refined(index)) TakeRefinedLine(index, carried->line_d_tangent);
      // Found under another id: from now on it is this pair's line (kept under its new id).
      if (id != reference_[i].id) line_map_.Erase(id);
    }
  }
  matches_.clear();
  // The lines placed by their endpoints count with the rest: the fraction of the reference left
  // (the tracker's reference policy) is of every line it measures, as are the survivors.
  return CountUsable(reference_) + placed;
}

int LineTransferModel::SetCurrent(const StereoFrame& frame) {
  last_pose_valid_ = false;
  CollectStereoLines(frame, &current_);
  // What a switch to this frame would gain leaves out the lines it would place by their
  // endpoints, unlike SetReference: those are placed far less precisely (sigma_along along each
  // segment), and counting them made the switches worse (docs/frontend.md, twenty-fifth pass).
  current_stereo_ = CountUsable(current_);
  matches_.clear();
  JoinById(reference_, current_, [&](size_t i, size_t j) {
    matches_.push_back({reference_[i].id, static_cast<int>(i), static_cast<int>(j)});
  });
  return static_cast<int>(matches_.size());
}

Eigen::Matrix4d LineTransferModel::NoiseCovariance(const Eigen::Matrix<double, 4, 16>& n, int bottom_zero_block) {
  // N N^T by 2x4 blocks, skipping the two that are zero by construction: the first residual pair
  // never sees the current right segment (columns 12-15), the second never sees one segment of
  // the first pair (columns `bottom_zero_block`..+3). Half the products of the dense 4x16 N N^T.
  Eigen::Matrix4d c = Eigen::Matrix4d::Zero();
  for (int b = 0; b < 16; b += 4) {
    const auto top = n.block<2, 4>(0, b);
    const auto bottom = n.block<2, 4>(2, b);
    if (b != 12) c.topLeftCorner<2, 2>().noalias() += top.lazyProduct(top.transpose());
    if (b != bottom_zero_block) c.bottomRightCorner<2, 2>().noalias() += bottom.lazyProduct(bottom.transpose());
    if (b != 12 && b != bottom_zero_block) c.topRightCorner<2, 2>().noalias() += top.lazyProduct(bottom.transpose());
  }
  c.bottomLeftCorner<2, 2>() = c.topRightCorner<2, 2>().transpose();
  return c;
}

Eigen::Vector2d LineTransferModel::Residual(const Eigen::Vector3d& line, const ObservedSegment& measured,
                                            const Eigen::Matrix3d& pixel_from_normalized, double fx,
                                            Eigen::Matrix<double, 2, 3>* d_line,
                                            Eigen::Matrix<double, 2, 4>* d_measured) const {
  Eigen::Vector2d r;
  if (distance_residual_) {
    const Eigen::Vector3d pixel_line = pixel_from_normalized * line;
    Eigen::Matrix<double, 1, 3> dl_a, dl_b;
    Eigen::Matrix<double, 1, 2> dp_a, dp_b;
    r(0) = SignedDistance(pixel_line, measured.segment.head<2>(), &dl_a, &dp_a);
    r(1) = SignedDistance(pixel_line, measured.segment.tail<2>(), &dl_b, &dp_b);
    d_line->row(0) = dl_a * pixel_from_normalized;
    d_line->row(1) = dl_b * pixel_from_normalized;
    if (d_measured) {
      d_measured->setZero();
      d_measured->block<1, 2>(0, 0) = dp_a;
      d_measured->block<1, 2>(1, 2) = dp_b;
    }
    return r;
  }
  // The paper's residual: measured minus predicted (theta, lambda), lambda in pixels.
  r = ThetaLambdaResidual(measured.line, line, d_line);
  r(1) *= fx;
  d_line->row(1) *= fx;
  if (d_measured) {
    Eigen::Matrix<double, 2, 3> d_measured_line;
    ThetaLambdaFromLine(measured.line, &d_measured_line);
    d_measured_line.row(1) *= fx;
    *d_measured = d_measured_line * measured.line_d_segment;
  }
  return r;
}

bool LineTransferModel::EndpointDistances(int index, const Rigid3d& cam_from_ref, Eigen::Vector4d* distances) const {
  const Match& match = matches_[index];
  const StereoLine& ref = reference_[match.reference];
  if (paper_direction_ || !distance_residual_ || (ref.degenerate && !reference_lines_[match.reference].refined)) {
    return false;
  }
  const StereoLine& cur = current_[match.current];
  const PlueckerLine& line = reference_lines_[match.reference].line;
  const Eigen::Vector3d left = left_pixel_from_normalized_ * TransformPluecker(cam_from_ref, line).moment;
  const Eigen::Vector3d right =
      right_pixel_from_normalized_ * TransformPluecker(RightFromRef(cam_from_ref), line).moment;
  *distances << SignedDistance(left, cur.left.segment.head<2>()), SignedDistance(left, cur.left.segment.tail<2>()),
      SignedDistance(right, cur.right.segment.head<2>()), SignedDistance(right, cur.right.segment.tail<2>());
  return distances->allFinite();
}

bool LineTransferModel::Evaluate(int index, const Rigid3d& cam_from_ref, bool with_covariance,
                                 FeatureBlock* block) const {
  const Match& match = matches_[index];
  const StereoLine& ref = reference_[match.reference];
  const StereoLine& cur = current_[match.current];
  // The reference pair defines the line in both directions, or the reference refinement
  // triangulated it.
  if (ref.degenerate && !reference_lines_[match.reference].refined) return false;
  block->measured_rows = FeatureBlock::kAllRows;
  // Noise Jacobian columns: endpoints of [ref left | ref right | cur left | cur right].
  Eigen::Matrix<double, 4, 16> noise_jacobian;
  Eigen::Matrix<double, 2, 3> d1, d2;
  Eigen::Matrix<double, 2, 4> m1, m2;
  Eigen::Matrix<double, 2, 4>* want_m1 = with_covariance && propagated_noise_ ? &m1 : nullptr;
  Eigen::Matrix<double, 2, 4>* want_m2 = with_covariance && propagated_noise_ ? &m2 : nullptr;
  const bool propagate = want_m1 != nullptr;
  Eigen::Matrix4d refined_covariance;
  const Eigen::Matrix4d* line_covariance = nullptr;

  if (paper_direction_) {
    CurrentToReferenceTransfer t;
    TransferCurrentToReference(rig_.right_from_left, cam_from_ref, ref.right.line, cur.left.line, cur.right.line,
                               true, &t);
    // Each transfer is gated on its own degeneracy (Sec. 4: "prevent a line transfer from
    // degeneracy"): T when the line nears the epipolar plane of I'_1 and I_t -- every line at
    // once when the current left camera passes the reference right one --, T' when it nears the
    // current pair's (horizontal lines). The other transfer still measures the line; dropping
    // the whole line there (as before) left too few lines and forced a new reference at a poor
    // pose: paper preset, seeds 1-200, 0.487 -> 0.421 deg at frame 100 (docs/derivations.md
    // Sec. 4).
    const bool via_T = t.via_T_plane_sine >= min_plane_sine_;
    const bool via_Tprime = !cur.degenerate && t.via_Tprime_plane_sine >= min_plane_sine_;
    if (!via_T && !via_Tprime) return false;
    block->measured_rows = (via_T ? 0x3u : 0u) | (via_Tprime ? 0xCu : 0u);
    // An unmeasured half gets zero derivatives (ClearUnmeasuredRows below clears its rows;
    // zeros keep the products that fill them finite).
    if (via_T) {
      block->residual.head<2>() =
          Residual(t.via_T, ref.left, left_pixel_from_normalized_, rig_.left.fx, &d1, want_m1);
    } else {
      d1.setZero();
      m1.setZero();
    }
    if (via_Tprime) {
      block->residual.tail<2>() =
          Residual(t.via_Tprime, ref.left, left_pixel_from_normalized_, rig_.left.fx, &d2, want_m2);
    } else {
      d2.setZero();
      m2.setZero();
    }
    block->jacobian.topRows<2>() = d1 * t.via_T_d_pose;
    block->jacobian.bottomRows<2>() = d2 * t.via_Tprime_d_pose;
    if (propagate) {
      noise_jacobian.block<2, 4>(0, 0) = m1;
      noise_jacobian.block<2, 4>(0, 4) = d1 * t.via_T_d_ref_right * ref.right.line_d_segment;
      noise_jacobian.block<2, 4>(0, 8) = d1 * t.via_T_d_cur_left * cur.left.line_d_segment;
      noise_jacobian.block<2, 4>(0, 12).setZero();
      noise_jacobian.block<2, 4>(2, 0) = m2;
      noise_jacobian.block<2, 4>(2, 4).setZero();
      noise_jacobian.block<2, 4>(2, 8) = d2 * t.via_Tprime_d_cur_left * cur.left.line_d_segment;
      noise_jacobian.block<2, 4>(2, 12) = d2 * t.via_Tprime_d_cur_right * cur.right.line_d_segment;
    }
  } else {
    // The reference pair's 3-D line (cached) imaged in the current pair: the trifocal transfer
    // with the current camera as the tensor's first view (geometry/plucker.h).
    const ReferenceLine& line = reference_lines_[match.reference];
    const Rigid3d& right_from_ref = RightFromRef(cam_from_ref);
    const PlueckerLine in_left = TransformPluecker(cam_from_ref, line.line);
    const PlueckerLine in_right = TransformPluecker(right_from_ref, line.line);
    block->residual.head<2>() =
        Residual(in_left.moment, cur.left, left_pixel_from_normalized_, rig_.left.fx, &d1, want_m1);
    block->residual.tail<2>() =
        Residual(in_right.moment, cur.right, right_pixel_from_normalized_, rig_.right.fx, &d2, want_m2);
    block->jacobian.topRows<2>() = ImageLinePoseJacobianProduct<2>(d1, in_left);
    // E Exp(d) M = Exp(Ad_E d) E M: the right camera is perturbed by Ad_E d.
    block->jacobian.bottomRows<2>().noalias() =
        ImageLinePoseJacobianProduct<2>(d2, in_right).lazyProduct(right_adjoint_);
    if (propagate) {
      const Eigen::Matrix<double, 2, 6> d1_line = ImageLineLineJacobianProduct<2>(d1, cam_from_ref);
      const Eigen::Matrix<double, 2, 6> d2_line = ImageLineLineJacobianProduct<2>(d2, right_from_ref);
      noise_jacobian.block<2, 4>(0, 0).noalias() = d1_line * line.line_d_left_segment;
      noise_jacobian.block<2, 4>(0, 4).noalias() = d1_line * line.line_d_right_segment;
      noise_jacobian.block<2, 4>(0, 8) = m1;
      noise_jacobian.block<2, 4>(0, 12).setZero();
      noise_jacobian.block<2, 4>(2, 0).noalias() = d2_line * line.line_d_left_segment;
      noise_jacobian.block<2, 4>(2, 4).noalias() = d2_line * line.line_d_right_segment;
      noise_jacobian.block<2, 4>(2, 8).setZero();
      noise_jacobian.block<2, 4>(2, 12) = m2;
      if (line.refined) {
        // The refined line's own uncertainty replaces the reference endpoints'.
        noise_jacobian.block<2, 8>(0, 0).setZero();
        noise_jacobian.block<2, 8>(2, 0).setZero();
        Eigen::Matrix<double, 4, 4> d_tangent;
        d_tangent.topRows<2>().noalias() = d1_line * line.line_d_tangent;
        d_tangent.bottomRows<2>().noalias() = d2_line * line.line_d_tangent;
        if (options_.consider_structure) {
          // As G G^T of EvaluateStructureJacobian, so that R - G G^T is the current noise also
          // for a line whose covariance is huge in a direction the residual barely sees (where
          // d C d^T and (d S)(d S)^T differ by their rounding).
          const Eigen::Matrix4d d_sqrt = d_tangent * line.tangent_sqrt_covariance;
          refined_covariance.noalias() = d_sqrt * d_sqrt.transpose();
        } else {
          refined_covariance.noalias() = d_tangent * line.tangent_covariance * d_tangent.transpose();
        }
        line_covariance = &refined_covariance;
      }
    }
  }
  if (with_covariance) {
    if (propagate) {
      const double var = options_.endpoint_sigma_px * options_.endpoint_sigma_px;
      block->covariance = var * NoiseCovariance(noise_jacobian, paper_direction_ ? 4 : 8);
      block->covariance.diagonal() += covariance_floor_;
      if (line_covariance) block->covariance += *line_covariance;
    } else {
      block->covariance = fixed_covariance_;
    }
  }
  block->ClearUnmeasuredRows(with_covariance);
  return true;
}

Eigen::Matrix<double, 4, 6> LineTransferModel::ResidualLineJacobian(const Match& match,
                                                                   const Rigid3d& cam_from_ref) const {
  const StereoLine& cur = current_[match.current];
  const PlueckerLine& line = reference_lines_[match.reference].line;
  const Rigid3d& right_from_ref = RightFromRef(cam_from_ref);
  Eigen::Matrix<double, 2, 3> d1, d2;
  Residual(TransformPluecker(cam_from_ref, line).moment, cur.left, left_pixel_from_normalized_, rig_.left.fx, &d1,
           nullptr);
  Residual(TransformPluecker(right_from_ref, line).moment, cur.right, right_pixel_from_normalized_, rig_.right.fx,
           &d2, nullptr);
  Eigen::Matrix<double, 4, 6> out;
  out.topRows<2>() = ImageLineLineJacobianProduct<2>(d1, cam_from_ref);
  out.bottomRows<2>() = ImageLineLineJacobianProduct<2>(d2, right_from_ref);
  return out;
}

bool LineTransferModel::EvaluateStructureJacobian(int index, const Rigid3d& cam_from_ref,
                                                  StructureJacobian* jacobian) const {
  const Match& match = matches_[index];
  const ReferenceLine& line = reference_lines_[match.reference];
  if (paper_direction_ || !propagated_noise_ || (reference_[match.reference].degenerate && !line.refined)) {
    return false;
  }
  // The same columns as the reference part of Evaluate's noise Jacobian (times sigma), or the
  // refined line's tangent: G G^T is the part of Evaluate's R the reference line contributes.
  const Eigen::Matrix<double, 4, 6> d_line = ResidualLineJacobian(match, cam_from_ref);
  if (line.refined) {
    jacobian->leftCols<4>().noalias() = d_line * line.line_d_tangent * line.tangent_sqrt_covariance;
    jacobian->rightCols<4>().setZero();
  } else {
    jacobian->leftCols<4>().noalias() = options_.endpoint_sigma_px * d_line * line.line_d_left_segment;
    jacobian->rightCols<4>().noalias() = options_.endpoint_sigma_px * d_line * line.line_d_right_segment;
  }
  return true;
}

bool LineTransferModel::PlaceByEndpoints(int index) {
  const StereoLine& ref = reference_[index];
  Segment2d right = ref.right.segment;
  if (StereoEndpointsSwapped(point_geometry_, ref.left.segment, right, kEndpointPairingAmbiguityPx)) {
    right << right.tail<2>(), right.head<2>();
  }
  ReferencePoint p, q;
  point_geometry_.Point(ref.left.segment.head<2>(), right.head<2>(), true, &p);
  point_geometry_.Point(ref.left.segment.tail<2>(), right.tail<2>(), true, &q);
  const Eigen::Vector3d pq = q.point - p.point;
  const double length = pq.norm();
  if (!(p.depth > kMinPlacedDepthM && q.depth > kMinPlacedDepthM) || !(length > 0.0) || !pq.allFinite()) return false;
  ReferenceLine& out = reference_lines_[index];
  out.line.direction = pq / length;
  out.line.moment = p.point.cross(out.line.direction);
  // d [n; d] / d [P; Q] for d = (Q - P) / |Q - P|, n = P x d.
  const Eigen::Matrix3d g = (Eigen::Matrix3d::Identity() - out.line.direction * out.line.direction.transpose()) / length;
  Eigen::Matrix<double, 6, 6> line_d_points;
  line_d_points.topLeftCorner<3, 3>() = -Skew(out.line.direction) - Skew(p.point) * g;
  line_d_points.topRightCorner<3, 3>() = Skew(p.point) * g;
  line_d_points.bottomLeftCorner<3, 3>() = -g;
  line_d_points.bottomRightCorner<3, 3>() = g;
  // The endpoints' covariance, per image point: sigma_along^2 t t^T + sigma^2 m m^T (t along its
  // segment, m across), in the order [x_P; x'_P; x_Q; x'_Q].
  const auto endpoint_covariance = [&](const Segment2d& segment) {
    const Eigen::Vector2d t = (segment.tail<2>() - segment.head<2>()).normalized(), m(-t.y(), t.x());
    return Eigen::Matrix2d(options_.endpoint_placement_sigma_px * options_.endpoint_placement_sigma_px * t *
                               t.transpose() +
                           options_.endpoint_sigma_px * options_.endpoint_sigma_px * m * m.transpose());
  };
  const Eigen::Matrix2d left_covariance = endpoint_covariance(ref.left.segment);
  const Eigen::Matrix2d right_covariance = endpoint_covariance(right);
  Eigen::Matrix<double, 8, 8> pixel_covariance = Eigen::Matrix<double, 8, 8>::Zero();
  for (int k = 0; k < 4; ++k) pixel_covariance.block<2, 2>(2 * k, 2 * k) = k % 2 == 0 ? left_covariance : right_covariance;
  Eigen::Matrix<double, 6, 8> points_d_pixels = Eigen::Matrix<double, 6, 8>::Zero();
  points_d_pixels.topLeftCorner<3, 4>() = p.point_d_pixels;
  points_d_pixels.bottomRightCorner<3, 4>() = q.point_d_pixels;
  double parameters[kLineAmbientSize];
  if (!LineToParameters(out.line, parameters)) return false;
  const Eigen::Matrix<double, 6, 4> basis = LineTangentBasis(parameters);
  const Eigen::Matrix<double, 4, 8> tangent_d_pixels = LineTangentFromAmbient(basis) * line_d_points * points_d_pixels;
  SetLineCovariance(basis, tangent_d_pixels * pixel_covariance * tangent_d_pixels.transpose(), &out);
  return true;
}

void LineTransferModel::SetLineCovariance(const Eigen::Matrix<double, 6, 4>& tangent_basis,
                                          const Eigen::Matrix4d& tangent_covariance, ReferenceLine* line) const {
  line->line_d_tangent = tangent_basis;
  line->tangent_covariance = tangent_covariance;
  if (options_.consider_structure) {
    // A square root of a positive semi-definite matrix (an LLT fails on a singular one).
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(tangent_covariance);
    line->tangent_sqrt_covariance = eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
  }
  line->refined = true;
}

void LineTransferModel::TakeRefinedLine(int index, const Eigen::Matrix<double, 6, 4>& tangent_basis) {
  ReferenceLine& line = reference_lines_[index];
  line.line = refiner_->Line(index);
  SetLineCovariance(tangent_basis, refiner_->Covariance(index), &line);
  ++line.version;
}

bool LineTransferModel::RefineStructure(const Rigid3d& cam_from_ref, const std::vector<int>& used,
                                        Rigid3d* refined_cam_from_ref) {
  solved_ = false;
  if (!refiner_) return false;
  last_cam_from_ref_ = cam_from_ref;
  last_pose_valid_ = true;
  if (!refiner_->CountFrame(cam_from_ref)) return false;
  // The features of the update, and the lines not measured yet because the reference pair
  // does not define them (the refinement triangulates them from the keyframes).
  keyframe_observations_.clear();
  auto add = [&](const Match& m) {
    const StereoLine& cur = current_[m.current];
    keyframe_observations_.push_back({m.reference, cur.left.segment, cur.right.segment, cur.left.line});
  };
  for (int index : used) add(matches_[index]);
  for (const Match& m : matches_) {
    if (reference_[m.reference].degenerate && !reference_lines_[m.reference].refined) add(m);
  }
  Rigid3d refined;
  if (!refiner_->AddKeyframeAndSolve(cam_from_ref, keyframe_observations_, &refined)) return false;
  for (int index = 0; index < static_cast<int>(reference_lines_.size()); ++index) {
    if (refiner_->Refined(index)) TakeRefinedLine(index, refiner_->TangentBasis(index));
    if (refiner_->HeldBack(index) && reference_lines_[index].refined) {
      reference_lines_[index].refined = false;
      ++reference_lines_[index].version;
    }
  }
  *refined_cam_from_ref = refined;
  solved_ = true;
  if (options_.refinement.move_pose) last_cam_from_ref_ = refined;
  return options_.refinement.move_pose;
}

FeatureModel::RefinedCovarianceUse LineTransferModel::RefinedPoseCovariance(const Matrix6d& filter_covariance,
                                                                           Matrix6d* covariance) const {
  const PoseCovarianceSource source = options_.refinement.pose_covariance;
  if (source == PoseCovarianceSource::kReportPlacement) {
    return solved_ && refiner_->ReferencePlacementCovariance(covariance) ? RefinedCovarianceUse::kReferencePlacement
                                                                         : RefinedCovarianceUse::kNone;
  }
  Matrix6d solved;
  if (!solved_ || !refiner_->NewestPoseCovariance(&solved)) return RefinedCovarianceUse::kNone;
  if (source == PoseCovarianceSource::kSolve) {
    *covariance = solved;
    return RefinedCovarianceUse::kFilter;
  }
  // The filter's widened to cover the solve's: P + (S - P)+.
  const Eigen::SelfAdjointEigenSolver<Matrix6d> excess(solved - filter_covariance);
  *covariance = filter_covariance + excess.eigenvectors() * excess.eigenvalues().cwiseMax(0.0).asDiagonal() *
                                        excess.eigenvectors().transpose();
  return source == PoseCovarianceSource::kCover ? RefinedCovarianceUse::kFilter : RefinedCovarianceUse::kReport;
}

}  // namespace slt
