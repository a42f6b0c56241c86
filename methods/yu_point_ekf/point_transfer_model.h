// The measurement model of Yu's point-trifocal EKF (yu_point_ekf.h): trifocal point transfer
// from the reference stereo pair into the current stereo pair.
//
// For a point seen as x in the reference left image I_1 and x' in the reference right image
// I'_1, and as y, y' in the current images I_t, I'_t, with M = cam_from_ref the current left
// camera and E = right_from_left:
//
//   l'   = the line through x' perpendicular to the epipolar line F x of x in I'_1 (pixels)
//   T    over (I_1, I'_1, I_t):   y_hat^k  = x^i l'_j T_i^{jk}      (P1 = [I|0], A = E, B = M)
//   T''  over (I_1, I'_1, I'_t):  y'_hat^k = x^i l'_j T''_i^{jk}    (P1 = [I|0], A = E, B = E M)
//   residual r = [y - y_hat; y' - y'_hat]  (pixels, 4 scalars)
//
// (Not the epipolar line itself: its plane E^T l' contains the ray of x, which it then does
// not cut, and the transfer vanishes.) Plane form, used here: the
// tensor contracted with x and l' is the image in view 3 of the point where the ray of x meets
// the plane pi' = E^T l' back-projected from l',
//   X = IntersectRayWithPlane(x, E^T l')          (reference left camera frame),
//   y_hat = K pi(M X),   y'_hat = K' pi(E M X),
// so X (and its Jacobian with respect to x and x') is computed once per reference and an
// evaluation is two projections. point_transfer_model_test.cc checks it against TransferPoint
// with TrifocalTensorFromCameras. X is x's ray triangulated against x' moved onto the epipolar
// line of x.
//
// Pose Jacobian under M <- Exp(d) M, d = [v; w]: with X_c = M X,
//   d X_c / d d = [I, -[X_c]_x],   d (E M X) / d d = R_E [I, -[X_c]_x]   (= the same through Ad_E),
// times the pinhole Jacobians of each camera; the residual's is minus that.
//
// Measurement covariance R:
//   noise "fixed": sigma^2 I (the paper's constant diagonal R), sigma = fixed_sigma_px;
//   noise "propagated": R = sigma^2 N N^T + floor^2 I, N the 4x8 Jacobian of r with respect
//     to the 8 pixel coordinates (x, x', y, y'), each with standard deviation sigma =
//     endpoint_sigma_px; x enters through its ray and through the epipolar line that sets l',
//     x' through l'. (The epipolar path vanishes on exact data, where l' turns about the ray of
//     x' that X lies on, and always in a rectified rig, whose epipolar lines keep their
//     direction; it matters for noisy points in a general rig.)
//
// Points and correspondences. The points are the endpoints of the stereo-lines/1 segments:
// each line id observed in both images of a frame gives two stereo point matches.
//   Stereo (within a frame): the pairing (a <-> a', b <-> b') or (a <-> b', b <-> a') whose
//     summed distance of the right endpoints to the epipolar lines of their left partners is
//     smaller (for the default rectified rig, the smaller |dv|); when the two sums differ by
//     less than 1 px (kPairingAmbiguityPx; a segment along the epipolar lines, where the rule is
//     decided by noise), the pairing that keeps the two segments' directions agreeing. On the
//     paper protocol (20 seeds, 79 922 stereo lines) this mis-pairs 6 lines noise-free and 124
//     at +-2.5 px; the epipolar distances alone 0 and 191, the directions alone 353 and 345
//     (receding lines reverse direction between the images).
//   Temporal (reference -> current, left image): endpoint k of a line in the reference left
//     image is matched with the endpoint of the current left segment in the same direction
//     along the line: the current order is kept when (b_t - a_t) . (b_1 - a_1) >= 0, reversed
//     otherwise. The direction test does not depend on how far the segment moved. (The rule
//     "nearest endpoint" fails once a segment moves along itself by more than half its length.)
//     The current right endpoints follow their stereo partners. On the paper protocol the
//     direction rule mis-pairs 0.13 % of the (line, frame) pairs against frame 0 (foreshortened
//     segments turning through more than 90 deg in the image); the gate drops them.
//   endpoint_pairing "given" (kGiven) skips both rules and trusts the observed order (the simulator's,
//   or a detector that orients segments by their gradient's sign, paper Sec. 3.1).
// A reference point is usable when X is at least min_depth_m in front of the reference camera
// and the ray of x meets the plane of l' at min_ray_plane_angle_deg or more (a far point or a
// near-zero disparity: the transfer's depth is then undefined); unusable points are not
// features. Features are indexed by (line id, reference endpoint) in increasing order:
// FeatureId(i) is the line id and FeatureEndpoint(i) = 0 for the reference left segment's
// first endpoint [u1 v1], 1 for its second [u2 v2]. A feature whose point is less than
// min_depth_m in front of a current camera at the evaluated pose is not measured there.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/json_reader.h"
#include "common/options.h"
#include "geometry/stereo_point.h"
#include "methods/stereo_ekf/feature_model.h"

namespace slt {

enum class EndpointPairing { kGeometric, kGiven };

// Every field's JSON key, range and one-line doc are declared once, in PointTransferOptionsSchema()
// (point_transfer_model.cc); the comments here say why a field exists.
struct PointTransferOptions {
  MeasurementNoise noise = MeasurementNoise::kPropagated;  // the paper's: kFixed
  // Standard deviation of each endpoint coordinate (uniform +-n px has sigma = n / sqrt(3)).
  double endpoint_sigma_px = 1.5;
  // Added (squared) to the diagonal of a propagated R.
  double covariance_floor_px = 0.05;
  // Fixed R: per residual scalar.
  double fixed_sigma_px = 2.0;
  // Usable reference points (and current depths): at least this far in front of the camera.
  double min_depth_m = 0.05;
  // Usable reference points: the ray of x and the plane E^T l' meet at least at this angle
  // (about the parallax of the point; 0.25 deg is a disparity of 3.7 px at f = 848.7 px,
  // 23 m away on a 0.1 m baseline).
  double min_ray_plane_angle_deg = 0.25;
  // kGeometric: endpoints paired by the rules above (any detector); kGiven: endpoint k of a
  // segment is endpoint k in every image and frame (the simulator's order, or a detector that
  // orients segments by their gradient's sign, as the paper's does in Sec. 3.1).
  EndpointPairing endpoint_pairing = EndpointPairing::kGeometric;

  void Check(const std::string& where = "point transfer options", const std::string& path = "") const;
};

const OptionSchema<PointTransferOptions>& PointTransferOptionsSchema();
void ReadPointTransferOptions(JsonReader& reader, PointTransferOptions* options);
nlohmann::json PointTransferOptionsToJson(const PointTransferOptions& options);

// A reference endpoint matched with a current one (PointTransferModel's features).
struct PointTransferMatch {
  std::int64_t id;
  int endpoint;         // reference endpoint k
  int reference_point;  // index into the reference points (2 * line + k)
  int current_line;     // index into the current lines
  int current_endpoint;
};

class PointTransferModel final : public MatchedFeatureModel<PointTransferMatch> {
 public:
  explicit PointTransferModel(const PointTransferOptions& options);

  void Reset(const StereoRig& rig) override;
  int SetReference(const StereoFrame& frame) override;
  int SetCurrent(const StereoFrame& frame) override;
  bool Evaluate(int index, const Rigid3d& cam_from_ref, bool with_covariance,
                FeatureBlock* block) const override;

  // The reference endpoint (0 or 1) of feature `index` (its line's id: FeatureId).
  int FeatureEndpoint(int index) const { return matches_[index].endpoint; }
  const StereoPointGeometry& geometry() const { return geometry_; }

 private:
  // A line seen in both images of a frame, its right endpoints reordered to pair with the left
  // ones (left[k] <-> right[k]).
  struct StereoLinePoints {
    std::int64_t id;
    Segment2d left_segment;
    std::array<Eigen::Vector2d, 2> left;
    std::array<Eigen::Vector2d, 2> right;
  };

  void CollectStereoLines(const StereoFrame& frame, std::vector<StereoLinePoints>* out);
  bool Usable(const ReferencePoint& point) const;

  PointTransferOptions options_;
  bool propagated_noise_ = true;
  bool geometric_pairing_ = true;
  double min_ray_plane_sine_ = 0.0;
  StereoRig rig_;
  StereoPointGeometry geometry_;

  std::vector<StereoLinePoints> reference_;
  std::vector<ReferencePoint> reference_points_;  // 2 per reference line
  std::vector<char> reference_usable_;            // parallel to reference_points_
  std::vector<StereoLinePoints> current_;
  // Scratch for CollectStereoLines, kept to avoid allocation per frame.
  std::vector<LineObservation> left_sorted_, right_sorted_;
};

}  // namespace slt
