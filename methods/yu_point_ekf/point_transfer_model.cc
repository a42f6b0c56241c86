#include "methods/yu_point_ekf/point_transfer_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dataset/association.h"
#include "geometry/line2d.h"
#include "geometry/se3.h"
#include "geometry/trifocal.h"
#include "methods/pose_tracker.h"

namespace slt {
namespace {

// Pixel projection of a point given in the camera's frame, with d pixel / d point.
inline Eigen::Vector2d ProjectToPixel(const PinholeCamera& camera, const Eigen::Vector3d& p,
                                      Eigen::Matrix<double, 2, 3>* d_point) {
  const double iz = 1.0 / p.z();
  const double x = p.x() * iz, y = p.y() * iz;
  *d_point << camera.fx * iz, 0.0, -camera.fx * x * iz,  //
      0.0, camera.fy * iz, -camera.fy * y * iz;
  return {camera.fx * x + camera.cx, camera.fy * y + camera.cy};
}

// Stereo endpoint pairing: below this difference (px) between the epipolar distances of the two
// pairings, the segments' directions decide.
constexpr double kPairingAmbiguityPx = 1.0;

}  // namespace

const OptionSchema<PointTransferOptions>& PointTransferOptionsSchema() {
  using O = PointTransferOptions;
  static const OptionSchema<O> schema =
      OptionSchema<O>()
          .Field("noise", &O::noise, MeasurementNoiseNames(),
                 "R propagated from the endpoint noise, or the paper's fixed sigma^2 I")
          .Field("endpoint_sigma_px", &O::endpoint_sigma_px, Positive(), "endpoint noise per coordinate (px), propagated R")
          .Field("covariance_floor_px", &O::covariance_floor_px, Positive(), "floor added to a propagated R (px)")
          .Field("fixed_sigma_px", &O::fixed_sigma_px, Positive(), "fixed R per residual scalar (px)")
          .Field("min_depth_m", &O::min_depth_m, Positive(), "points nearer to a camera are not measured (m)")
          .Field("min_ray_plane_angle_deg", &O::min_ray_plane_angle_deg, InRange(0.0, 90.0, "[)"),
                 "reference points whose ray meets the transfer plane at less are not used")
          .Field("endpoint_pairing", &O::endpoint_pairing,
                 {{EndpointPairing::kGeometric, "geometric"}, {EndpointPairing::kGiven, "given"}},
                 "pair endpoints by epipolar and direction rules, or trust the observed order");
  return schema;
}

void PointTransferOptions::Check(const std::string& where, const std::string& path) const {
  PointTransferOptionsSchema().Validate(*this, where, path);
}

void ReadPointTransferOptions(JsonReader& r, PointTransferOptions* o) { PointTransferOptionsSchema().Read(r, o); }

nlohmann::json PointTransferOptionsToJson(const PointTransferOptions& o) { return PointTransferOptionsSchema().ToJson(o); }

// ---------------------------------------------------------------------------------------------
// PointTransferModel

PointTransferModel::PointTransferModel(const PointTransferOptions& options) : options_(options) {
  options_.Check();
  propagated_noise_ = options_.noise == MeasurementNoise::kPropagated;
  geometric_pairing_ = options_.endpoint_pairing == EndpointPairing::kGeometric;
  min_ray_plane_sine_ = std::sin(options_.min_ray_plane_angle_deg * M_PI / 180.0);
}

void PointTransferModel::Reset(const StereoRig& rig) {
  rig_ = rig;
  geometry_ = StereoPointGeometry(rig);
  reference_.clear();
  reference_points_.clear();
  reference_usable_.clear();
  current_.clear();
  matches_.clear();
  current_stereo_ = 0;
}

bool PointTransferModel::Usable(const ReferencePoint& point) const {
  return point.point.allFinite() && point.depth >= options_.min_depth_m &&
         point.ray_plane_sine >= min_ray_plane_sine_;
}

void PointTransferModel::CollectStereoLines(const StereoFrame& frame, std::vector<StereoLinePoints>* out) {
  const std::vector<LineObservation>& left = SortedById(frame.left, &left_sorted_);
  const std::vector<LineObservation>& right = SortedById(frame.right, &right_sorted_);
  out->clear();
  JoinById(left, right, [&](size_t i, size_t j) {
    const Segment2d& l = left[i].segment;
    const Segment2d& r = right[j].segment;
    if (!UsableSegment(l) || !UsableSegment(r)) return;
    StereoLinePoints line;
    line.id = left[i].id;
    line.left_segment = l;
    line.left = {l.head<2>(), l.tail<2>()};
    const bool swap = geometric_pairing_ && StereoEndpointsSwapped(geometry_, l, r, kPairingAmbiguityPx);
    line.right = {r.segment<2>(swap ? 2 : 0), r.segment<2>(swap ? 0 : 2)};
    out->push_back(line);
  });
}

int PointTransferModel::SetReference(const StereoFrame& frame) {
  CollectStereoLines(frame, &reference_);
  reference_points_.resize(2 * reference_.size());
  reference_usable_.resize(2 * reference_.size());
  int usable = 0;
  for (size_t i = 0; i < reference_.size(); ++i) {
    for (int k = 0; k < 2; ++k) {
      ReferencePoint& point = reference_points_[2 * i + k];
      geometry_.Point(reference_[i].left[k], reference_[i].right[k], true, &point);
      reference_usable_[2 * i + k] = Usable(point) && point.point_d_pixels.allFinite();
      usable += reference_usable_[2 * i + k];
    }
  }
  matches_.clear();
  return usable;
}

int PointTransferModel::SetCurrent(const StereoFrame& frame) {
  CollectStereoLines(frame, &current_);
  current_stereo_ = 0;
  ReferencePoint point;
  for (const StereoLinePoints& line : current_) {
    for (int k = 0; k < 2; ++k) {
      geometry_.Point(line.left[k], line.right[k], false, &point);
      current_stereo_ += Usable(point);
    }
  }
  matches_.clear();
  JoinById(reference_, current_, [&](size_t i, size_t j) {
    const bool swap =
        geometric_pairing_ && TemporalEndpointsSwapped(reference_[i].left_segment, current_[j].left_segment);
    for (int k = 0; k < 2; ++k) {
      const int point = static_cast<int>(2 * i) + k;
      if (!reference_usable_[point]) continue;
      matches_.push_back({reference_[i].id, k, point, static_cast<int>(j), swap ? 1 - k : k});
    }
  });
  return static_cast<int>(matches_.size());
}

bool PointTransferModel::Evaluate(int index, const Rigid3d& cam_from_ref, bool with_covariance,
                                  FeatureBlock* block) const {
  const Match& match = matches_[index];
  const ReferencePoint& ref = reference_points_[match.reference_point];
  const StereoLinePoints& cur = current_[match.current_line];
  const Rigid3d& e = rig_.right_from_left;
  block->measured_rows = FeatureBlock::kAllRows;
  // X in the current left and right cameras: the plane form of the two point transfers.
  const Eigen::Vector3d x_left = cam_from_ref * ref.point;
  const Eigen::Vector3d x_right = e * x_left;
  if (!(x_left.z() >= options_.min_depth_m && x_right.z() >= options_.min_depth_m)) return false;
  Eigen::Matrix<double, 2, 3> d_left, d_right;
  block->residual.head<2>() = cur.left[match.current_endpoint] - ProjectToPixel(rig_.left, x_left, &d_left);
  block->residual.tail<2>() = cur.right[match.current_endpoint] - ProjectToPixel(rig_.right, x_right, &d_right);
  // d X_c / d d = [I, -[X_c]_x]; the right camera adds R_E in front (E Exp(d) M = Exp(Ad_E d) E M).
  const Eigen::Matrix3d skew = Skew(x_left);
  const Eigen::Matrix<double, 2, 3> d_right_rotated = d_right.lazyProduct(e.rotation);
  block->jacobian.block<2, 3>(0, 0) = -d_left;
  block->jacobian.block<2, 3>(0, 3).noalias() = d_left.lazyProduct(skew);
  block->jacobian.block<2, 3>(2, 0) = -d_right_rotated;
  block->jacobian.block<2, 3>(2, 3).noalias() = d_right_rotated.lazyProduct(skew);
  if (!with_covariance) return true;
  if (!propagated_noise_) {
    block->covariance = Eigen::Matrix4d::Identity() * (options_.fixed_sigma_px * options_.fixed_sigma_px);
    return true;
  }
  // N = [N_ref | I_4]: the reference pixels through X, the current pixels directly.
  const Eigen::Matrix<double, 3, 4> x_d_pixels = cam_from_ref.rotation.lazyProduct(ref.point_d_pixels);
  Eigen::Matrix4d n_ref;
  n_ref.topRows<2>().noalias() = -d_left.lazyProduct(x_d_pixels);
  n_ref.bottomRows<2>().noalias() = -d_right_rotated.lazyProduct(x_d_pixels);
  const double var = options_.endpoint_sigma_px * options_.endpoint_sigma_px;
  block->covariance.noalias() = var * n_ref.lazyProduct(n_ref.transpose());
  block->covariance.diagonal().array() += var + options_.covariance_floor_px * options_.covariance_floor_px;
  return true;
}

}  // namespace slt
