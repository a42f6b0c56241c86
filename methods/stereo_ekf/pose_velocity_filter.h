// The state and covariance bookkeeping of the stereo EKF: the pose of the current left camera
// relative to the reference pair, M_t = cam_from_ref, and the body-frame velocity xi (a twist
// per frame), with a 12-D error state e = [d; dv]:
//   true M_t  = Exp(d) M_t,     true xi = xi + dv.
// Motion model (eq. 11 and 18, body frame: docs/derivations.md):
//   xi_t = xi_{t-1} + eta,  eta ~ N(0, Q);    M_t = Exp(xi_t) M_{t-1}
// whose error propagation is e_t = F e_{t-1} with
//   F = [[Ad(Exp(xi)), J_l(xi)], [0, I]],    P_t|t-1 = F (P + diag(0, q^2 Q)) F^T,
// q^2 = 1 unless the tracker adapts it (SetProcessNoiseScale; docs/derivations.md, "Adapted Q").
// With state FilterState::kVelocity (the paper's filter, eq. 10), the pose block is reset to zero before
// every prediction: M_{t-1} is taken as exact and only the velocity is estimated.
//
// Measurements inform the pose only (their Jacobian is [H 0]), so an update is a MAP solve on
// the pose with the pose-marginal prior (done by the tracker), followed here by the Gaussian
// conditional for the velocity: with G = P_vp P_pp^-1,
//   dv = G d,   P_vv+ = P_vv - G (P_pp - P_pp+) G^T,   P_vp+ = G P_pp+.
#pragma once

#include <Eigen/Core>

#include "geometry/se3.h"
#include "methods/stereo_ekf/stereo_ekf_options.h"

namespace slt {

class PoseVelocityFilter {
 public:
  using Matrix12d = Eigen::Matrix<double, 12, 12>;
  using Vector12d = Eigen::Matrix<double, 12, 1>;

  void Reset(const StereoEkfOptions& options);
  void Predict();
  // The pose Predict() will give, M_t|t-1 = Exp(xi) M_{t-1}, without changing the state.
  Rigid3d PredictedCamFromRef() const;
  // `prior_pose_information` is P_pp^-1 at the prediction (the caller has it already).
  void Correct(const Vector6d& delta, const Matrix6d& posterior_pose_covariance,
               const Matrix6d& prior_pose_information);
  // The update of a filter whose measurements also depend on consider parameters
  // (structure_consider.h): the correction [d; dv] of pose and velocity and their posterior
  // covariance, both computed by the caller.
  void CorrectState(const Vector12d& delta, const Matrix12d& posterior_covariance);
  // Replaces pose and velocity after a detected failure: the pose from a measurement-only
  // solve with its covariance, and the initial (wide) velocity prior centred on the motion from
  // the previous pose when that pose is trusted, on zero otherwise (a previous pose from a
  // filter that had already gone wrong would turn the whole correction into a velocity and
  // carry the next predictions off by as much again).
  void Reseed(const Rigid3d& cam_from_ref, const Matrix6d& pose_covariance, bool previous_pose_trusted);
  // While nothing is measured: xi <- f xi, so that a lost tracker coasts briefly and then holds
  // its pose instead of extrapolating, frame after frame, a velocity nobody confirms (a wrong
  // update just before the loss made such runs drift by metres). The covariance is left as it
  // is: it already grows by Q every frame, and inflating it further (toward the initial prior)
  // widened the gate and let outliers in when the features came back (measured on the
  // feature-count sweep with 20-30 % outliers).
  void DampVelocity(double factor);
  // Moves the pose to `cam_from_ref` (re-estimated with refined structure), keeping the
  // velocity and the covariance.
  void MovePose(const Rigid3d& cam_from_ref) { cam_from_ref_ = cam_from_ref; }
  // Moves the pose to `cam_from_ref` with covariance `pose_covariance` (a smoother's marginal:
  // the reference refinement's newest keyframe). The pose error is mapped by
  //     T = pose_covariance^1/2 P_pp^-1/2   (symmetric square roots),
  // e_pose <- T e_pose, so that P_pp becomes pose_covariance and P_vp its correlation with the
  // velocity scaled alike (P stays positive semi-definite); a singular P_pp (no pose
  // uncertainty yet) gives T = 0: P_pp = pose_covariance, uncorrelated. Returns T, which the
  // caller applies to whatever else is correlated with the pose error.
  Matrix6d MovePose(const Rigid3d& cam_from_ref, const Matrix6d& pose_covariance);
  // The current camera becomes the reference: the relative pose is exactly the identity.
  void StartNewReferencePair();
  // Q of the next predictions is multiplied by `scale_sq` (1 after Reset).
  void SetProcessNoiseScale(double scale_sq) { process_noise_scale_sq_ = scale_sq; }
  double process_noise_scale_sq() const { return process_noise_scale_sq_; }

  const Rigid3d& cam_from_ref() const { return cam_from_ref_; }
  const Rigid3d& previous_cam_from_ref() const { return previous_cam_from_ref_; }
  const Vector6d& velocity() const { return velocity_; }
  Matrix6d PoseCovariance() const { return covariance_.topLeftCorner<6, 6>(); }
  const Matrix12d& covariance() const { return covariance_; }
  // F of the last Predict(): e_t = F e_t-1 (the identity before the first).
  const Matrix12d& transition() const { return transition_; }

 private:
  Matrix6d InitialVelocityCovariance() const;
  // The motion of one frame, Exp(xi) (or its first-order form).
  Rigid3d Step() const;

  StereoEkfOptions options_;
  Rigid3d cam_from_ref_;
  Rigid3d previous_cam_from_ref_;
  Vector6d velocity_ = Vector6d::Zero();
  Matrix12d covariance_ = Matrix12d::Zero();
  Matrix12d transition_ = Matrix12d::Identity();
  double process_noise_scale_sq_ = 1.0;
};

}  // namespace slt
