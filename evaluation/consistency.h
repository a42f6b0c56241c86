// Consistency of a tracker's pose covariance against the ground truth: the normalised estimation
// error squared (NEES) and the fraction of errors beyond three standard deviations, computed the
// way OpenVINS's ov_eval computes them (ResultTrajectory::calculate_nees and calculate_error:
// orientation and position NEES separately, no alignment, per-axis error against its sigma).
// docs/metrics.md gives the formulas.
//
// Convention of the covariance (methods/pose_tracker.h, docs/conventions.md): the true
// cam_from_world is ExpSE3(d) * estimate with d = [v; w] ~ N(0, P) in the current camera frame.
// Per associated pose, with T = cam_from_world:
//   d        = LogSE3(T_gt * T_est^-1)                 NEES      = d^T P^-1 d          (6 dof)
//   e_rot    = w = Log(R_gt R_est^T) (camera frame)    NEES_rot  = e_rot^T P_ww^-1 e_rot (3 dof)
//   e_pos    = c_gt - c_est (camera centres, world)    NEES_pos  = e_pos^T P_c^-1 e_pos  (3 dof)
//   with P_c = R_est^T P_vv R_est, the position covariance in the world to first order.
// Beyond 3 sigma: over the six axes (the three of e_rot against sqrt(diag P_ww), the three of
// e_pos against sqrt(diag P_c)) and every pose, the fraction with |e| > 3 sigma; 0.27 % for a
// consistent Gaussian estimate.
// A consistent estimator has mean NEES = the degrees of freedom; over N independent trials the
// mean of the per-trial NEES at one frame lies in NeesBand(0.95, dof, N) with probability 95 %.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "dataset/trajectory.h"
#include "evaluation/metrics.h"
#include "evaluation/statistics.h"
#include "geometry/se3.h"

namespace slt {

struct ConsistencyErrors {
  size_t associated_poses = 0;
  size_t used_poses = 0;          // associated poses with a positive-definite covariance
  ErrorStatistics nees;           // 6 dof, per pose
  ErrorStatistics nees_rot;       // 3 dof
  ErrorStatistics nees_pos;       // 3 dof
  double beyond_3sigma_fraction = 0.0;  // over every (pose, axis), six axes per pose
  std::vector<double> per_frame_nees;   // 6-dof NEES of each used pose, in time order
};

// `covariances[i]` belongs to est[i] (world_from_cam poses, as in a trajectory file). Poses are
// associated by time as EvaluateTrajectory does, with no alignment (both worlds are the first
// left camera). Covariances that are not positive definite are skipped (a tracker without one
// gives zeros). Throws std::invalid_argument when the sizes differ or no pose is usable.
ConsistencyErrors EvaluateConsistency(const Trajectory& gt, const Trajectory& est,
                                      const std::vector<Matrix6d>& covariances, double max_time_diff_s = 0.01);

// The two-sided `probability` interval of the mean of `trials` independent chi-square(dof)
// values: chi-square(trials * dof) quantiles divided by trials.
std::pair<double, double> NeesBand(double probability, int dof, int trials);

nlohmann::json ToJson(const ConsistencyErrors& consistency);

// The covariances of a `track --log` file (columns cov_<i><j>, i <= j, docs/formats.md), one per
// row; a row with empty fields (a tracker without a covariance) gives zero. Throws
// std::runtime_error naming the file and column when a column is missing or unreadable.
std::vector<Matrix6d> ReadLogCovariances(const std::string& path);

}  // namespace slt
