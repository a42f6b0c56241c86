// Trajectory accuracy metrics, defined the way evo (github.com/MichaelGrupp/evo) defines
// them, plus the paper's "accumulated error" curves. docs/metrics.md gives every formula.
//
// Poses are world_from_cam of the left camera (dataset/trajectory.h). Errors are reported in
// metres and degrees; every name carries its unit.
//   - association: each estimate pose is paired with the nearest ground-truth pose in time
//     within max_time_diff_s; a ground-truth pose is used at most once.
//   - alignment (optional): the similarity that best maps the estimated positions onto the
//     ground-truth ones (Umeyama), applied to the estimate.
//   - ATE: per associated pose, ||t_est - t_gt|| and angle(R_gt^T R_est) (evo_ape with
//     translation_part / angle_deg).
//   - RPE: per pair (i, i + delta), E = (Q_i^-1 Q_{i+delta})^-1 (P_i^-1 P_{i+delta}) with Q the
//     ground truth and P the estimate; ||t(E)|| and angle(R(E)) (evo_rpe, delta in frames).
//   - per-frame curve: the ATE errors of each pose in time order; its last entry is the final
//     error and, with no alignment, its value at frame k is the paper's accumulated error.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "dataset/trajectory.h"
#include "evaluation/statistics.h"
#include "geometry/rigid3.h"

namespace slt {

enum class Alignment {
  kNone,  // both trajectories already share the world (the left camera at the first frame)
  kSE3,   // rotation and translation
  kSim3,  // rotation, translation and scale
};
const char* AlignmentName(Alignment alignment);  // "none", "se3", "sim3"
// Throws std::invalid_argument listing the valid names.
Alignment AlignmentFromName(const std::string& name);

struct EvaluationOptions {
  double max_time_diff_s = 0.01;  // association window (evo's --t_max_diff)
  Alignment alignment = Alignment::kNone;
  int rpe_delta_frames = 1;       // RPE step, in associated poses (evo's --delta, --delta_unit f)
  bool rpe_all_pairs = false;     // pairs (i, i + delta) for every i instead of i = 0, delta, 2 delta, ...

  // Throws ConfigError "<where>: key '<field>': <reason>".
  void Check(const std::string& where = "evaluation options") const;
};

// Indices of a ground-truth and an estimate pose that were associated.
struct PosePair {
  size_t gt_index = 0;
  size_t est_index = 0;
};

// Pairs each estimate pose with the ground-truth pose nearest in time, if it is within
// max_time_diff_s (ties go to the earlier ground-truth pose). When several estimate poses pick
// the same ground-truth pose, the nearest in time keeps it (ties: the earlier estimate pose) and
// the others stay unpaired. Both trajectories must have non-decreasing times
// (std::invalid_argument otherwise). The result is in estimate order; it may be empty.
std::vector<PosePair> AssociateByTime(const Trajectory& gt, const Trajectory& est, double max_time_diff_s);

// target ~= scale * rotation * source + translation.
struct SimilarityTransform {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double scale = 1.0;

  Eigen::Vector3d operator*(const Eigen::Vector3d& point) const { return scale * (rotation * point) + translation; }
  // Moves a camera pose given in the source world into the target world: the camera centre
  // maps as a point, the orientation is rotated; the result is again a rigid pose.
  Rigid3d Apply(const Rigid3d& world_from_cam) const {
    return Rigid3d(rotation * world_from_cam.rotation, *this * world_from_cam.translation);
  }
};

// Least-squares similarity (with_scale) or rigid transform (scale fixed to 1) mapping `source`
// onto `target` (Umeyama, IEEE PAMI 13(4), 1991). Throws std::invalid_argument when the sizes
// differ or the points are fewer than 3, coincident or collinear (the rotation about their
// line is then undetermined).
SimilarityTransform UmeyamaAlignment(const std::vector<Eigen::Vector3d>& source,
                                     const std::vector<Eigen::Vector3d>& target, bool with_scale);


// The error of one estimate pose against its ground-truth pose.
struct FrameError {
  int frame = 0;        // index of the ground-truth pose (0 = the first frame)
  double time_s = 0.0;  // its time
  double trans_err_m = 0.0;
  double rot_err_deg = 0.0;
};
// In time order, one entry per associated pose.
using ErrorCurve = std::vector<FrameError>;

struct TrajectoryErrors {
  EvaluationOptions options;
  size_t gt_poses = 0;
  size_t est_poses = 0;
  size_t associated_poses = 0;
  // gt_world_from_est_world as applied to the estimate (identity for Alignment::kNone).
  SimilarityTransform alignment;
  ErrorStatistics ate_trans_m;
  ErrorStatistics ate_rot_deg;
  ErrorStatistics rpe_trans_m;  // count = number of RPE pairs
  ErrorStatistics rpe_rot_deg;
  ErrorCurve per_frame;

  const FrameError& Final() const { return per_frame.back(); }
};

// Associates, aligns and measures. Throws ConfigError when the options are invalid and
// std::invalid_argument when nothing associates, fewer than rpe_delta_frames + 1 poses
// associate, or the alignment is undetermined.
TrajectoryErrors EvaluateTrajectory(const Trajectory& gt, const Trajectory& est, const EvaluationOptions& options);

// {"alignment": .., "ate_trans_m": {"rmse": .., ...}, ..., "final_trans_err_m": ..}; the
// per-frame curve only when include_per_frame (it has one entry per pose).
nlohmann::json ToJson(const TrajectoryErrors& errors, bool include_per_frame);
nlohmann::json ToJson(const ErrorStatistics& statistics);
nlohmann::json ToJson(const ErrorCurve& curve);

// The KITTI odometry benchmark's metric (Geiger, Lenz, Urtasun, "Are we ready for autonomous
// driving?", CVPR 2012; the devkit's evaluate_odometry.cpp). After association by time (no
// alignment), with d(k) the ground truth's path length up to pose k: for every first pose
// i = 0, step, 2 step, ... and every length L, the first pose j with d(j) > d(i) + L (segments
// running past the end are skipped),
//   E = (P_i^-1 P_j)^-1 (Q_i^-1 Q_j)      (P the estimate, Q the ground truth),
// translational error ||t(E)|| / L and rotational error angle(R(E)) / L. Reported as their
// means over all segments: trans_err_pct = 100 * mean ||t(E)|| / L (the devkit's %) and
// rot_err_deg_per_m = mean angle(R(E)) / L in degrees per metre; and per length.
struct KittiOdometryOptions {
  std::vector<double> segment_lengths_m = {100, 200, 300, 400, 500, 600, 700, 800};
  int step_frames = 10;  // first poses every step_frames associated poses
  double max_time_diff_s = 0.01;

  // Throws ConfigError "<where>: key '<field>': <reason>".
  void Check(const std::string& where = "KITTI odometry options") const;
};

struct KittiSegmentErrors {
  double length_m = 0.0;
  int segments = 0;
  double trans_err_pct = 0.0;      // means over the segments of this length (NaN when none)
  double rot_err_deg_per_m = 0.0;
};

struct KittiOdometryErrors {
  KittiOdometryOptions options;
  double path_length_m = 0.0;  // of the associated ground truth
  int segments = 0;            // 0 when the sequence is shorter than every length
  double trans_err_pct = 0.0;  // NaN when there are no segments
  double rot_err_deg_per_m = 0.0;
  std::vector<KittiSegmentErrors> per_length;
};

// Throws std::invalid_argument when nothing associates (as EvaluateTrajectory).
KittiOdometryErrors EvaluateKittiOdometry(const Trajectory& gt, const Trajectory& est, const KittiOdometryOptions& options);
// {"segments": .., "trans_err_pct": .., "rot_err_deg_per_m": .., "per_length": [...]} (null
// for the means without segments).
nlohmann::json ToJson(const KittiOdometryErrors& errors);

// The paper's accumulated error over trials (Fig. 4-6): at each frame, the mean over trials
// of the translation and rotation errors. Every curve must cover the same frames (throws
// std::invalid_argument otherwise, or when there are no curves); time_s is averaged too.
ErrorCurve MeanErrorCurve(const std::vector<ErrorCurve>& trials);
// The entry of `frame`; throws std::out_of_range when the curve does not have it.
const FrameError& ErrorAtFrame(const ErrorCurve& curve, int frame);

}  // namespace slt
