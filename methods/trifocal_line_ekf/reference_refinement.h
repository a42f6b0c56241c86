// Joint refinement of the reference pair's 3-D lines with keyframe poses (issue 16; beyond the
// paper, which keeps the lines of the reference pair as its stereo pair defines them).
//
// The trifocal EKF (direction reference_to_current) measures every frame against the lines L_i
// of the reference pair, triangulated from that one stereo pair (geometry/plucker.h
// StereoPairLine). Their endpoint noise is frozen into L_i for as long as the reference is
// kept -- hundreds of frames in a room --, so it biases every pose measured against it; a
// white-noise filter can neither average it out nor describe it (docs/long_sequences.md).
// While a reference pair is kept, this class stores keyframes K_k (every keyframe_interval
// measured frames, once the camera is keyframe_min_distance_m from the last one; beyond max_keyframes the one nearest its successor is dropped, which keeps the
// widest parallax) with the filter's pose M_k = cam_from_ref and
// the segments of the reference lines they observe, and after each new keyframe solves the
// small bundle adjustment
//     min over L_i, M_k   sum_i sum_{c in {left, right}} rho(|r(C_c, L_i; s_i1c)|^2)
//                       + sum_k sum_{i seen in K_k} sum_c rho(|r(C_c M_k, L_i; s_ikc)|^2),
// with r Taylor & Kriegman's segment residual (optim/taylor_segment_cost.h, weight 1) or, with
// segment_residual "endpoints", the endpoints' distances to the projected line,
// C_left = I, C_right = the rig's right_from_left, the reference pair's pose the identity
// (held fixed: the gauge) and the rig fixed (the scale), rho the Huber loss. Lines on the
// 4-dof manifold, poses on SE(3) (optim/line_sfm_manifolds.h, shared with the Taylor
// baseline). Lines the reference pair does not define (near an epipolar plane) are triangulated
// once a keyframe sees them at min_triangulation_angle_deg from the reference's left image: in
// a room these are the horizontal lines across the view, the ones that measure the vertical
// translation when the camera moves along the other horizontal lines. They stay out of the
// joint solve (their small-parallax errors bent its poses); after it each is refined alone
// against the solved poses, held fixed, with the same residuals, and reaches the filter only
// through a consistency gate: its position's standard deviation (marginal covariance, the
// poses' uncertainty included) at most triangulated_max_sigma_m and its residual sum within the
// chi-square quantile triangulated_gate_probability.
//
// The tracker then measures against the refined L_i, with the reference endpoints' noise
// replaced by the lines' own covariance C_i (the line's block of the inverse of the problem's
// Gauss-Newton information: marginalised over the keyframe poses, the correlations between
// lines left out), and with move_pose moves the current pose to the solved newest keyframe's
// pose (the current frame is that keyframe); with pose_covariance it also uses that keyframe's
// marginal covariance (all the lines' uncertainty and correlations in it) for the filter's or
// the reported pose covariance. Measured effect: docs/long_sequences.md.
// Up to 64 keyframes the solve and the covariances eliminate the lines (a reduced system over
// the poses); a larger window (max_keyframes, e.g. every 5th frame of a whole reference pair's
// life) eliminates the poses instead (a reduced system over the lines,
// optim/line_pose_marginals.h), whose cost grows with the lines rather than cubically with
// the keyframes. The two agree up to rounding; the switch keeps earlier results to the bit.
//
// Repeatable to the bit: Ceres orders the blocks of each elimination group by address, so the
// blocks of a solve live in buffers whose address order is their index order (the lines in
// lines_, the poses in pose_parameters_), never in separately allocated nodes.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "common/options.h"
#include "dataset/stereo_sequence.h"
#include "geometry/line2d.h"
#include "geometry/plucker.h"
#include "optim/line_sfm_manifolds.h"
#include "optim/taylor_segment_cost.h"

namespace slt {

enum class PoseCovarianceSource { kFilter, kSolve, kCover, kReportCover, kReportPlacement };

// Every field's key, range and doc are declared once, in ReferenceRefinementOptionsSchema().
struct ReferenceRefinementOptions {
  bool enabled = false;
  int keyframe_interval = 10;  // measured frames between keyframes (at least)
  // A keyframe also needs its camera centre this far from the previous keyframe's (the
  // reference pair's for the first): on a slow camera, keyframes by count alone are too close to
  // add parallax. 0 = by count only.
  double keyframe_min_distance_m = 0.0;
  int max_keyframes = 32;      // keyframes kept (beyond: the one nearest its successor is dropped)
  int max_iterations = 10;     // Levenberg-Marquardt steps per solve
  double huber_sigma = 2.0;    // Huber threshold on the whitened segment residual
  // The segment residual (optim/taylor_segment_cost.h): Taylor's (weight 1, sigma the endpoint
  // sigma / sqrt(2)) or the endpoints' distances (sigma the endpoint sigma), which weighs the
  // tilt of a line three times as much as Taylor's does. Taylor's by default: on the room loop
  // the endpoints' alone changes the means little; with the triangulated lines
  // (min_triangulation_angle_deg) it is the most accurate setting measured (docs/long_sequences.md).
  SegmentResidual segment_residual = SegmentResidual::kTaylor;
  // The current pose follows the refined newest keyframe. Off: with 32 keyframes the room
  // loop's maximum error is lower without it (docs/long_sequences.md).
  bool move_pose = false;
  // After each solve, the filter's pose covariance (PoseVelocityFilter::MovePose, its
  // correlations with the velocity and the lines mapped alike; with move_pose, about the refined
  // pose): kFilter keeps the filter's own; kSolve takes the solve's marginal covariance of the
  // newest keyframe, the current frame (the lines' uncertainty and all their correlations
  // included, which the filter's per-line consider parameters leave out, and without counting
  // twice what the refined lines and the filter's prior both learnt from the same frames);
  // kCover widens the filter's to cover the solve's, P + (S - P)+ (the positive part of the
  // difference): only the directions where the filter claims more than the window's data give;
  // kReportCover leaves the filter's (and so every estimate) as it is and widens only the
  // reported covariance so, by (S - P)+, until the next solve. kReportPlacement also leaves
  // every estimate as it is and adds to the reported covariance the reference pair's placement
  // relative to its lines (ReferencePlacementCovariance): an error common to all the refined
  // lines, which the filter's per-line consider parameters count as independent per line and
  // so average away.
  PoseCovarianceSource pose_covariance = PoseCovarianceSource::kFilter;
  // The endpoint noise (sigma per coordinate, px) the solve weighs its residuals by; 0 = the
  // measurement model's endpoint_sigma_px. The filter's fixed R may be set above the images'
  // noise to cover what it does not model; the solve's covariance, which pose_covariance hands
  // to the filter, is only as right as this sigma.
  double endpoint_sigma_px = 0.0;
  // Lines the reference pair does not define (near an epipolar plane: horizontal lines of a
  // horizontal rig) are triangulated from the reference's left image and a keyframe's once
  // their back-projected planes meet at this angle, then refined like the others. 0 = never
  // (the default: on the room loop, 10 trials, it did not change the ATE beyond the spread
  // between seeds and made the covariance far too confident; docs/long_sequences.md).
  double min_triangulation_angle_deg = 0.0;
  // Consistency gate of those triangulated lines: after each solve one is given to the filter
  // only when its position is determined (the largest standard deviation of its tangent's
  // moment part, its marginal covariance from the solve, at most triangulated_max_sigma_m) and
  // its whitened residuals over the reference and the keyframes pass a chi-square test
  // (sum <= the triangulated_gate_probability quantile, 2 dof per segment minus 4). Otherwise it
  // stays in its solve but the filter does not measure it. 0 = no bound / no test (the
  // defaults: on the room loop the gate, 5 cm and 0.99, made the ATE worse; docs/long_sequences.md).
  double triangulated_max_sigma_m = 0.0;
  double triangulated_gate_probability = 0.0;
  // A new reference pair starts from the refined lines it shares with the previous one, moved
  // into its frame with the current pose and kept as priors (SetCarriedLine), instead of their
  // stereo triangulation from the new pair alone.
  bool carry_over = true;
  // With carry_over, the refined lines of earlier reference pairs too, kept for map_max_age
  // pairs after the last one that refined them, and found by id or, with map_association_px,
  // by their projection into the new pair within that many px (reference_line_map.h).
  // 0 and 0: the previous pair's lines by id only, the plain carry-over. Off by default:
  // measured on the paper scene's images only (docs/frontend.md, twenty-sixth pass).
  int map_max_age = 0;
  double map_association_px = 0.0;

  void Check(const std::string& where = "reference refinement options", const std::string& path = "") const;
};

const OptionSchema<ReferenceRefinementOptions>& ReferenceRefinementOptionsSchema();

class ReferenceRefiner {
 public:
  // `endpoint_sigma_px`: the endpoint noise per coordinate, as the measurement model's.
  ReferenceRefiner(const ReferenceRefinementOptions& options, double endpoint_sigma_px);

  void Reset(const StereoRig& rig);
  // Forgets every keyframe and line; the new reference pair then has `lines` lines, none
  // refined, each to be given by SetLine.
  void StartReference(int lines);
  // Line `index` of the reference pair: its stereo line (reference frame) and its segments in
  // the reference pair, whose left line (normalised) is `left_line`. `usable` false: the pair
  // does not define it; it waits for a keyframe to triangulate it.
  void SetLine(int index, const PlueckerLine& line, bool usable, const Segment2d& left, const Segment2d& right,
               const Eigen::Vector3d& left_line);

  // Line `index` carried over from the previous reference pair: `line` (this reference's frame)
  // with the covariance of its tangent, kept in every solve as a prior (Minus(L, line) ~
  // N(0, covariance)), so that what earlier keyframes measured is not lost with them.
  void SetCarriedLine(int index, const PlueckerLine& line, const Eigen::Matrix4d& covariance);

  // One observation of a keyframe: reference line `line` seen with these segments; left_line
  // is the left segment's normalised line.
  struct Observation {
    int line;
    Segment2d left, right;
    Eigen::Vector3d left_line;
  };
  // Counts one measured frame, at `cam_from_ref`; true when it is to be a keyframe.
  bool CountFrame(const Rigid3d& cam_from_ref);
  // Adds a keyframe at `cam_from_ref` and solves. True when the solve succeeded; then
  // *newest_cam_from_ref is the keyframe's refined pose and Line / Covariance / Refined give the
  // refined structure.
  bool AddKeyframeAndSolve(const Rigid3d& cam_from_ref, const std::vector<Observation>& observations,
                           Rigid3d* newest_cam_from_ref);

  // The marginal covariance of the newest keyframe's pose in the last successful solve
  // (PoseManifold's left tangent, relative to the reference pair: the lines' uncertainty and
  // their correlations included). False when that solve left the poses undetermined, or when
  // pose_covariance is kFilter (then it is not computed).
  bool NewestPoseCovariance(Matrix6d* covariance) const {
    if (newest_covariance_valid_) *covariance = newest_covariance_;
    return newest_covariance_valid_;
  }

  // The covariance of the reference pair's placement relative to its lines in the last
  // successful solve: the inverse of the information its own segments give about its pose (the
  // solve's gauge, held fixed; PoseManifold's left tangent). A rigid motion of the lines and the
  // keyframes together changes no keyframe's residual, so only the reference pair's segments
  // (and carried lines' priors, not counted here) determine it, however many keyframes the
  // solve has: an error every pose measured against these lines keeps (docs/long_sequences.md).
  // False when that information is not positive definite, or when pose_covariance is not
  // kReportPlacement (then it is not computed).
  bool ReferencePlacementCovariance(Matrix6d* covariance) const {
    if (placement_valid_) *covariance = placement_covariance_;
    return placement_valid_;
  }

  bool Refined(int index) const { return lines_[index].refined; }
  // A triangulated line the last solve refined but the consistency gate held back: the filter
  // must stop measuring it.
  bool HeldBack(int index) const { return lines_[index].held_back; }
  PlueckerLine Line(int index) const { return LineFromParameters(lines_[index].parameters); }
  // Covariance of the line's 4-dof tangent (LineManifold) and the 6x4 Jacobian of [n; d]
  // with respect to it.
  const Eigen::Matrix4d& Covariance(int index) const { return lines_[index].covariance; }
  Eigen::Matrix<double, 6, 4> TangentBasis(int index) const;

  int solves() const { return solves_; }

 private:
  struct LineState {
    // Zero until set: a line the reference pair does not define keeps no parameters, and the
    // solve's finiteness check reads every line's.
    double parameters[kLineAmbientSize] = {};
    bool usable = false;
    bool refined = false;
    bool triangulated = false;  // from a keyframe's temporal parallax (not the stereo pair)
    bool held_back = false;     // triangulated, refined, and failed the gate in the last solve
    Segment2d left, right;  // in the reference pair
    Eigen::Vector3d left_line;
    Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();
    int observations = 0;  // per solve: keyframe segments
    std::unique_ptr<ceres::CostFunction> prior_cost;  // carried over: its prior residual (else null)
    Eigen::Matrix4d prior_sqrt_information;
  };
  struct Keyframe {
    double pose[kPoseAmbientSize];
    std::vector<Observation> observations;
  };

  // After the joint solve: the lines triangulated from keyframes, each refined alone against
  // the solved poses and gated (reference_refinement.cc).
  template <typename PoseOf, typename OffsetOfPose>
  void RefineTriangulatedLines(const PoseOf& pose_of, const OffsetOfPose& offset_of_pose,
                               const Eigen::MatrixXd& pose_covariance, const ceres::Problem& solved, size_t* used);

  ReferenceRefinementOptions options_;
  double sigma_px_;  // of the segment residual
  double min_triangulation_sine_;
  SegmentCamera cameras_[2];
  PoseManifold pose_manifold_;
  LineManifold line_manifold_;
  std::unique_ptr<ceres::LossFunction> loss_;
  ceres::Solver::Options solver_options_;
  // The pose blocks of the last solve: the reference pair's, then the keyframes' in window order
  // (one buffer, so that Ceres's address order is this order).
  std::vector<double> pose_parameters_;

  std::vector<LineState> lines_;
  std::deque<Keyframe> keyframes_;
  int frames_since_keyframe_ = 0;
  int solves_ = 0;
  Matrix6d newest_covariance_ = Matrix6d::Zero();
  bool newest_covariance_valid_ = false;
  Matrix6d placement_covariance_ = Matrix6d::Zero();
  bool placement_valid_ = false;
  std::deque<TaylorSegmentCost> costs_;  // reused from solve to solve (addresses kept)
  struct ResidualRef {
    const double* pose;
    int line;
  };
  std::vector<ResidualRef> residuals_;  // of the last problem, parallel to costs_
};

}  // namespace slt
