// The stereo EKF's update when the reference structure's error is a "consider" parameter
// (Schmidt-Kalman filter; issue 16, beyond the paper).
//
// Every frame is measured against the same reference structure (the trifocal EKF's reference
// lines, triangulated from one stereo pair or refined): its error is fixed while the reference
// pair is kept, not new in each frame. A filter that adds its covariance to R as white noise
// (R_i = R_current + G_i G_i^T per feature) counts it again in every frame, so the pose
// covariance shrinks below what that error allows and the pose absorbs it frame after frame.
// Here each structure s has a standard normal error u_s ~ N(0, I) (FeatureModel::
// EvaluateStructureJacobian gives G_i = d r_i / d u_s) and the filter keeps the cross-covariance
// Q_s = Cov(e, u_s) of its 12-D error state e = [d; dv] with every u_s, without estimating u
// (Schmidt: the structure is not updated and Cov(u) stays I; the state's update is the
// optimal one given the joint Gaussian).
//
// The update, in coordinates where the prior is N(0, I) (P = L L^T, e = L e~, Q~_s = L^+ Q_s),
// with the whitened feature i (D_i = R_current + G_i G_i^T = L_i L_i^T; r~ = L_i^-1 r, J~, G~):
// conditioning u on e~, u_s = Q~_s^T e~ + w_s with Cov(w_s, w_t) = delta_st I - Q~_s^T Q~_t, so
//   r~_i = A_i e~ + G~_i w_s + n~_i,   A_i = J~_i L_p + V_i,   V_i = G~_i Q~_s^T   (4 x 12),
//   noise covariance W = I - V V^T,    W^-1 = I + V N^-1 V^T,  N = I - V^T V   (Woodbury),
//   information  Lambda = I + A^T A + (A^T V) N^-1 (A^T V)^T     (12 x 12, a sum of PSD terms),
//   e~+ = Lambda^-1 (A^T nu + (A^T V) N^-1 V^T nu),   nu_i = -(r~_i - J~_i d_k)  (iterated step),
//   P+ = L Lambda^-1 L^T,
//   Q~_s+ = Q~_s - (K~ J^) Q~_s - K~_i G~_i  (the last term if feature i measures s),
//   K~ = Lambda^-1 A^T W^-1,   J^_i = J~_i L_p;   Q_s+ = L Q~_s+.
// (L from the eigen-decomposition of P, which is singular after a start or a new reference pair:
// the pose error is then the velocity's.)
// (The covariance form of the same update, P - T S^-1 T^T with S^-1 by Woodbury, lost positive
// definiteness on the room loop: prior and measurement information differ by 10^8.)
// Each step costs O(features x 12^2) plus O(structures x 12^2 x 8) for the cross-covariances.
// Prediction: Q_s <- F Q_s (pose_velocity_filter.h). A structure whose estimate the model
// replaced (StructureVersion changed), a re-seeded filter and a new reference pair start again
// from Q = 0.
#pragma once

#include <Eigen/Core>
#include <Eigen/Cholesky>
#include <vector>

#include "methods/stereo_ekf/feature_model.h"
#include "methods/stereo_ekf/least_squares.h"
#include "methods/stereo_ekf/pose_velocity_filter.h"

namespace slt {

class StructureConsider {
 public:
  using Matrix12d = PoseVelocityFilter::Matrix12d;
  using Vector12d = PoseVelocityFilter::Vector12d;
  using CrossCovariance = Eigen::Matrix<double, 12, FeatureModel::kStructureNoiseSize>;

  // The model's structures of a new reference pair, each uncorrelated with the filter.
  void Reset(const FeatureModel& model);
  // Forgets every correlation (the filter was re-seeded).
  void Clear();
  // Zeroes the cross-covariance of every structure whose estimate the model replaced.
  void Sync(const FeatureModel& model);
  void Predict(const Matrix12d& transition);
  // The filter's pose error was mapped by e_pose <- t e_pose (PoseVelocityFilter::MovePose):
  // the pose rows of every cross-covariance follow.
  void TransformPose(const Matrix6d& t);

  // The whitened structure Jacobian G~_i = L_i^-1 scale G_i of feature `index` at `cam_from_ref`,
  // the pose its covariance factor L_i was computed at, so that G~ G~^T <= I (scale: the square
  // root of the tracker's noise scale, which multiplies R). False when the model gives none.
  bool Linearize(const FeatureModel& model, const WeightedFeature& feature, int index,
                 const Rigid3d& cam_from_ref, double scale);
  // One iterated-EKF step from the pose correction `delta_k` (relative to the prediction) on
  // `inliers` (whitened at delta_k, linearised by Linearize): sets *delta (12-D, relative to
  // the prediction) and *posterior (P+). False when the step is not finite.
  bool Solve(const std::vector<WeightedFeature>& features, const std::vector<int>& inliers,
             const Matrix12d& covariance, const Vector6d& delta_k, Vector12d* delta, Matrix12d* posterior);
  // Applies the cross-covariance update of the last Solve (to be called once, after it).
  void Commit(const std::vector<int>& inliers);

  int size() const { return static_cast<int>(cross_.size()); }
  const CrossCovariance& cross_covariance(int structure) const { return cross_[structure]; }

 private:
  std::vector<CrossCovariance> cross_;
  // Nonzero once structure s has been measured since its cross-covariance was last zeroed: the
  // others are zero and stay zero until measured, so Predict and Commit skip them (most of a
  // pair's lines are never measured: stereo-degenerate ones).
  std::vector<char> correlated_;
  std::vector<int> versions_;
  // Per feature index (sized like the tracker's features), valid for the inliers of the last
  // Linearize / Solve.
  std::vector<FeatureModel::StructureJacobian> whitened_jacobian_;
  std::vector<int> structure_;
  std::vector<Eigen::Matrix<double, 4, 12>> j_;  // J^_i
  std::vector<Eigen::Matrix<double, 4, 12>> v_;  // V_i
  // Of the last Solve.
  Matrix12d lower_;          // L: P = L L^T
  Matrix12d lower_inverse_;  // L^+
  Eigen::LLT<Matrix12d> information_llt_;
  Matrix12d atv_ninv_;
  Matrix12d kj_;
};

}  // namespace slt
