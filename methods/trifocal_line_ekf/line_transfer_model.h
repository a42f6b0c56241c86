// The measurement model of the trifocal-line EKF (paper Sec. 3.2 and 4, eq. 13-17).
//
// For a line m seen in the reference pair (l_1, l'_1) and in the current pair (l_t, l'_t),
// with M = cam_from_ref the current left camera and E = right_from_left:
//
//   direction "current_to_reference" (the paper's, eq. 16):
//     T  over (I_1, I'_1, I_t):  L_1 = T(l'_1, l_t)       [l_1]_i = [l'_1]_j [l_t]_k T_i^jk
//     T' over (I_1, I_t, I'_t):  L_2 = T'(l_t, l'_t)      [l_1]_i = [l_t]_j [l'_t]_k T'_i^jk
//     both predict the measured reference line l_1 in I_1;
//   direction "reference_to_current":
//     L_1 = the reference pair transferred into I_t, L_2 into I'_t (the current camera as the
//     tensor's first view); they predict the current lines l_t and l'_t.
//
// with T_i = a_i b_4^T - a_4 b_i^T (eq. 17) evaluated through back-projected planes
// (geometry/trifocal.h). Each predicted line gives two residual scalars against its measured
// segment (4 per line, so two lines over-determine the pose):
//   residual "endpoint_distance": signed distances (px) of the measured segment's endpoints
//     to the predicted line;
//   residual "theta_lambda": the paper's slope/polar-radius difference [d theta (rad);
//     d lambda (px)] with theta = atan2(b, a), lambda = -c / |(a, b)| of the normalised line,
//     lambda scaled by fx (replaces the garbled eq. 8-9; docs/derivations.md).
// Measurement covariance R:
//   noise "fixed": the paper's constant diagonal R;
//   noise "propagated": R = sigma^2 N N^T + floor, N the Jacobian of the 4 residuals with
//     respect to the 16 endpoint coordinates of the four observed segments.
// A reference line in an epipolar plane of the rig is not defined by the pair and not measured,
// unless the reference refinement triangulates it from keyframes or endpoint_placement_sigma_px
// places it by its endpoints (below; docs/derivations.md): then its 3-D line L is projected,
// l_t = K^-T (M L).moment, and R carries L's own covariance instead of the reference endpoints'.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "common/json_reader.h"
#include "common/options.h"
#include "geometry/plucker.h"
#include "geometry/stereo_point.h"
#include "methods/stereo_ekf/feature_model.h"
#include "methods/trifocal_line_ekf/reference_line_map.h"
#include "methods/trifocal_line_ekf/reference_refinement.h"

namespace slt {

enum class TransferDirection { kCurrentToReference, kReferenceToCurrent };
enum class LineResidual { kEndpointDistance, kThetaLambda };

// Which stereo pairs define a line to measure, for every tracker measuring with this model
// (trifocal_line_ekf, elqursh_three_line; its key stands flat among theirs). Lines closer than
// min_epipolar_angle_deg to the epipolar direction in the left image (at the segment's middle)
// are not measured: a stereo pair does not define a line in an epipolar plane (horizontal lines
// in a horizontal rig), and near it the transfer is too non-linear for the linearised
// covariance. Checked on the reference pair, and on the current pair for the paper's direction,
// whose transfers start from it. An image criterion, unlike the angle between the back-projected
// planes, does not also reject distant lines.
struct EpipolarLineOptions {
  double min_epipolar_angle_deg = 3.0;
};

const OptionSchema<EpipolarLineOptions>& EpipolarLineOptionsSchema();

// Every field's JSON key, range and one-line doc are declared once, in LineTransferOptionsSchema()
// (line_transfer_model.cc); the comments here say why a field exists.
struct LineTransferOptions {
  TransferDirection direction = TransferDirection::kReferenceToCurrent;  // the paper's: kCurrentToReference
  LineResidual residual = LineResidual::kEndpointDistance;
  MeasurementNoise noise = MeasurementNoise::kPropagated;
  // Standard deviation of each endpoint coordinate (uniform +-n px has sigma = n / sqrt(3)).
  double endpoint_sigma_px = 1.5;
  // Added to the diagonal of a propagated R: just after a new reference pair (M ~ I) the two
  // transfers return the same line and R is nearly singular. (The theta rows of the
  // (theta, lambda) residual get kCovarianceFloorRad.)
  double covariance_floor_px = 0.05;
  // Fixed R: per residual scalar. fixed_sigma_px serves lambda and the endpoint distances;
  // fixed_sigma_rad, theta. The paper preset sets the spread measured for its (theta, lambda)
  // residual at +-2.5 px (0.012 rad, 1.9 px; trifocal_line_ekf.cc); the endpoint distances
  // spread 2.2 px there.
  double fixed_sigma_px = 2.0;
  double fixed_sigma_rad = 0.012;
  EpipolarLineOptions epipolar;
  // Lines whose extent across the epipolar lines (segment length times the sine of that angle,
  // px) is below this are not measured either: a short segment's measured angle is mostly its
  // endpoint noise, so a line in an epipolar plane can pass the angle test and be triangulated
  // at any depth. 0 = off.
  double min_epipolar_extent_px = 0.0;
  // Lines in an epipolar plane of the reference pair (the two tests above), which the transfer
  // cannot measure, placed instead by their endpoints (0 = off): each end of the left segment
  // and its partner in the right segment taken as one 3-D point (geometry/stereo_point.h: in a
  // rectified rig, the point at their disparity), the line through the two points measured like
  // a refined line, its covariance propagated from the endpoints with this standard deviation
  // along each segment (where a detector's endpoints err) and endpoint_sigma_px across it. In a
  // horizontal rig these are the horizontal lines, the only lines of a view of walls and shelves
  // that measure the vertical translation (docs/frontend.md, twenty-fourth pass). The ends of a
  // segment are not always one 3-D point in both images (an end occluded in one of them): such a
  // line is placed at a wrong depth, which the gate must catch. Direction reference_to_current
  // with the propagated R only.
  double endpoint_placement_sigma_px = 0.0;
  // Direction kCurrentToReference only: features whose transfer intersects two planes at less
  // than this angle are not measured either (lines near the trifocal plane of the views a
  // transfer uses, Sec. 4; this also rejects distant lines). 0 = off; the paper preset uses 3.
  double min_plane_angle_deg = 0.0;
  // Joint refinement of the reference lines with keyframe poses (reference_refinement.h; issue
  // 16). Direction kReferenceToCurrent with the propagated R only.
  ReferenceRefinementOptions refinement;
  // The reference lines' error as consider parameters of the filter (Schmidt-Kalman,
  // methods/stereo_ekf/structure_consider.h): the filter keeps its correlation with each line's
  // error instead of counting that error as new noise in every frame. Per line: the 8
  // reference endpoint coordinates (sigma endpoint_sigma_px each) of a stereo line, the 4-dof
  // tangent of a refined one. Direction reference_to_current with the propagated R only.
  bool consider_structure = false;

  void Check(const std::string& where = "line transfer options", const std::string& path = "") const;
};

const OptionSchema<LineTransferOptions>& LineTransferOptionsSchema();
void ReadLineTransferOptions(JsonReader& reader, LineTransferOptions* options);
nlohmann::json LineTransferOptionsToJson(const LineTransferOptions& options);

// A reference line matched with a current one (LineTransferModel's features).
struct LineTransferMatch {
  std::int64_t id;
  int reference;  // index into the reference lines
  int current;    // index into the current lines
};

class LineTransferModel final : public MatchedFeatureModel<LineTransferMatch> {
 public:
  // One observed segment with its normalised line (unit norm) and the Jacobian of that line
  // with respect to the segment's endpoints (scaled consistently with the unit norm; the
  // residuals are invariant to the line's positive scale, see docs/derivations.md).
  struct ObservedSegment {
    Segment2d segment;
    Eigen::Vector3d line;
    Eigen::Matrix<double, 3, 4> line_d_segment;
  };
  struct StereoLine {
    std::int64_t id;
    ObservedSegment left, right;
    bool degenerate;  // within min_epipolar_angle_deg of the epipolar direction
  };
  explicit LineTransferModel(const LineTransferOptions& options);

  void Reset(const StereoRig& rig) override;
  int SetReference(const StereoFrame& frame) override;
  int SetCurrent(const StereoFrame& frame) override;
  bool Evaluate(int index, const Rigid3d& cam_from_ref, bool with_covariance,
                FeatureBlock* block) const override;
  bool RefineStructure(const Rigid3d& cam_from_ref, const std::vector<int>& used,
                       Rigid3d* refined_cam_from_ref) override;
  RefinedCovarianceUse RefinedPoseCovariance(const Matrix6d& filter_covariance, Matrix6d* covariance) const override;
  bool DescribesStructure() const override { return options_.consider_structure; }
  int NumStructures() const override { return static_cast<int>(reference_lines_.size()); }
  int StructureOf(int index) const override { return matches_[index].reference; }
  int StructureVersion(int structure) const override { return reference_lines_[structure].version; }
  bool EvaluateStructureJacobian(int index, const Rigid3d& cam_from_ref, StructureJacobian* jacobian) const override;

  // The observations of feature `index` in the reference and the current pair, and the
  // reference pair's 3-D line in the reference frame (StereoPairLine): for methods
  // that use this model's matching and residuals with solvers of their own
  // (methods/elqursh_three_line).
  const StereoLine& ReferenceObservation(int index) const { return reference_[matches_[index].reference]; }
  const StereoLine& CurrentObservation(int index) const { return current_[matches_[index].current]; }
  const PlueckerLine& ReferenceLine3d(int index) const { return reference_lines_[matches_[index].reference].line; }
  // The four signed endpoint distances (px) of Evaluate's residual without its Jacobian, for
  // scoring many poses (RANSAC): direction reference_to_current with the endpoint_distance
  // residual only (false for the other settings, and where Evaluate is false).
  bool EndpointDistances(int index, const Rigid3d& cam_from_ref, Eigen::Vector4d* distances) const;

 private:
  // Per reference line, for direction "reference_to_current": the 3-D line of the pair
  // (l_1, l'_1) in the reference frame, computed once per reference, with the Jacobians of
  // [n; d] with respect to the endpoints of the left and right segments.
  struct ReferenceLine {
    PlueckerLine line;
    Eigen::Matrix<double, 6, 4> line_d_left_segment;
    Eigen::Matrix<double, 6, 4> line_d_right_segment;
    // Refined by the reference refinement: `line` is the refined line, whose uncertainty is
    // line_d_tangent C line_d_tangent^T (C = tangent_covariance) instead of the endpoints'.
    bool refined = false;
    Eigen::Matrix<double, 6, 4> line_d_tangent;
    Eigen::Matrix4d tangent_covariance;
    Eigen::Matrix4d tangent_sqrt_covariance;  // S S^T = tangent_covariance (consider_structure)
    int version = 0;                          // counts the estimates the line has had
  };
  // Stereo-matched lines of a frame, sorted by id, into `out`.
  void CollectStereoLines(const StereoFrame& frame, std::vector<StereoLine>* out);
  // Reference line `index` becomes the refiner's refined line, with the covariance of its
  // tangent and that tangent's basis (at the line, LineManifold).
  void TakeRefinedLine(int index, const Eigen::Matrix<double, 6, 4>& tangent_basis);
  // Reference line `index` (in an epipolar plane) placed by its endpoints
  // (endpoint_placement_sigma_px); false (the line left unmeasured) when an end is not in front
  // of the cameras.
  bool PlaceByEndpoints(int index);
  // A placed or refined line's uncertainty: its tangent basis and covariance (and the square
  // root the consider update uses); marks it refined.
  void SetLineCovariance(const Eigen::Matrix<double, 6, 4>& tangent_basis, const Eigen::Matrix4d& tangent_covariance,
                         ReferenceLine* line) const;
  bool MakeSegment(const Segment2d& segment, const PinholeCamera& camera, ObservedSegment* out) const;
  static int CountUsable(const std::vector<StereoLine>& lines);
  // True if the left segment lies within min_epipolar_angle_deg of its epipolar line.
  bool NearEpipolar(const ObservedSegment& left) const;
  // N N^T for the 4x16 noise Jacobian, whose blocks (0..1, 12..15) and (2..3, bottom_zero_block..+3)
  // are zero.
  static Eigen::Matrix4d NoiseCovariance(const Eigen::Matrix<double, 4, 16>& n, int bottom_zero_block);
  // Two residual scalars of predicted normalised line `line` (in a view with intrinsics of
  // `pixel_from_normalized` = K^-T and fx) against `measured`, with their Jacobians with respect
  // to the predicted line and to the measured segment's endpoints.
  Eigen::Vector2d Residual(const Eigen::Vector3d& line, const ObservedSegment& measured,
                           const Eigen::Matrix3d& pixel_from_normalized, double fx,
                           Eigen::Matrix<double, 2, 3>* d_line, Eigen::Matrix<double, 2, 4>* d_measured) const;

  // d residual / d [n; d] of the reference line of match `match` at `cam_from_ref` (direction
  // reference_to_current): rows 0-1 the left image's residual, 2-3 the right's.
  Eigen::Matrix<double, 4, 6> ResidualLineJacobian(const Match& match, const Rigid3d& cam_from_ref) const;

  // right_from_left * cam_from_ref, cached for the last pose asked.
  const Rigid3d& RightFromRef(const Rigid3d& cam_from_ref) const;

  LineTransferOptions options_;
  bool paper_direction_ = true;
  bool distance_residual_ = true;
  bool propagated_noise_ = true;
  double min_epipolar_sine_ = 0.0;
  double min_plane_sine_ = 0.0;
  Eigen::Vector3d left_epipole_;  // the right camera's centre in the left camera (normalised, homogeneous)
  StereoRig rig_;
  StereoPointGeometry point_geometry_;
  Eigen::Matrix3d left_pixel_from_normalized_;
  Eigen::Matrix3d right_pixel_from_normalized_;
  Matrix6d right_adjoint_;  // Ad(right_from_left)
  mutable Rigid3d cached_cam_from_ref_;
  mutable Rigid3d cached_right_from_ref_;
  Eigen::Matrix4d fixed_covariance_;
  Eigen::Vector4d covariance_floor_;

  std::unique_ptr<ReferenceRefiner> refiner_;  // when refinement.enabled
  std::vector<ReferenceRefiner::Observation> keyframe_observations_;  // scratch
  // The last RefineStructure solved (its newest keyframe is the current frame: the refiner's
  // NewestPoseCovariance is this frame's).
  bool solved_ = false;
  // The pose of the last frame given to RefineStructure (after its move), valid until the next
  // SetCurrent: a new reference pair taken at that frame carries the refined lines over with it.
  Rigid3d last_cam_from_ref_;
  bool last_pose_valid_ = false;
  // The refined lines carried into new reference pairs (refinement.carry_over).
  ReferenceLineMap line_map_;

  std::vector<StereoLine> reference_;
  std::vector<ReferenceLine> reference_lines_;  // parallel to reference_
  std::vector<StereoLine> current_;
  // Scratch for CollectStereoLines, kept to avoid allocation per frame.
  std::vector<LineObservation> left_sorted_, right_sorted_;
};

}  // namespace slt
