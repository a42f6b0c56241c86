#include "methods/stereo_ekf/pose_velocity_filter.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace slt {

Matrix6d PoseVelocityFilter::InitialVelocityCovariance() const {
  Vector6d sigma;
  sigma << Eigen::Vector3d::Constant(options_.initial_velocity_sigma_m),
      Eigen::Vector3d::Constant(options_.initial_velocity_sigma_rad);
  return sigma.array().square().matrix().asDiagonal();
}

void PoseVelocityFilter::Reset(const StereoEkfOptions& options) {
  options_ = options;
  cam_from_ref_ = Rigid3d();
  previous_cam_from_ref_ = Rigid3d();
  velocity_.setZero();
  covariance_.setZero();
  covariance_.bottomRightCorner<6, 6>() = InitialVelocityCovariance();
  transition_.setIdentity();
  process_noise_scale_sq_ = 1.0;
}

Rigid3d PoseVelocityFilter::Step() const {
  return options_.integration == Integration::kFirstOrder ? FirstOrderSE3(velocity_) : ExpSE3(velocity_);
}

Rigid3d PoseVelocityFilter::PredictedCamFromRef() const { return Step() * cam_from_ref_; }

void PoseVelocityFilter::Predict() {
  if (options_.state == FilterState::kVelocity) {
    // The paper's filter: M_{t-1} is exact, only the velocity is uncertain.
    covariance_.topRows<6>().setZero();
    covariance_.leftCols<6>().setZero();
  }
  // Velocity random walk first: the new velocity is the one integrated into the pose.
  const double qm = process_noise_scale_sq_ * options_.accel_sigma_m * options_.accel_sigma_m;
  const double qr = process_noise_scale_sq_ * options_.accel_sigma_rad * options_.accel_sigma_rad;
  for (int i = 6; i < 9; ++i) covariance_(i, i) += qm;
  for (int i = 9; i < 12; ++i) covariance_(i, i) += qr;

  const Rigid3d step = Step();
  // F = [[Ad(step), J_l(xi)], [0, I]]; P <- F P F^T, written blockwise.
  const Matrix6d ad = Adjoint(step);
  // J_l to first order: per-frame twists are small and it only enters the covariance.
  const Matrix6d jl = LeftJacobianSE3FirstOrder(velocity_);
  // With F = [[A, B], [0, I]]: Y = A P_pv + B P_vv is the new P_pv, and
  // P_pp <- (A P_pp + B P_vp) A^T + Y B^T (six 6x6 products).
  const Matrix6d Ppp = covariance_.topLeftCorner<6, 6>();
  const Matrix6d Ppv = covariance_.topRightCorner<6, 6>();
  const Matrix6d Pvv = covariance_.bottomRightCorner<6, 6>();
  Matrix6d x, y;
  x.noalias() = ad.lazyProduct(Ppp);
  x.noalias() += jl.lazyProduct(Ppv.transpose());
  y.noalias() = ad.lazyProduct(Ppv);
  y.noalias() += jl.lazyProduct(Pvv);
  Matrix6d new_pp;
  new_pp.noalias() = x.lazyProduct(ad.transpose());
  new_pp.noalias() += y.lazyProduct(jl.transpose());
  covariance_.topLeftCorner<6, 6>() = 0.5 * (new_pp + new_pp.transpose());
  transition_.topLeftCorner<6, 6>() = ad;
  transition_.topRightCorner<6, 6>() = jl;
  covariance_.topRightCorner<6, 6>() = y;
  covariance_.bottomLeftCorner<6, 6>() = y.transpose();

  previous_cam_from_ref_ = cam_from_ref_;
  cam_from_ref_ = step * cam_from_ref_;
}

void PoseVelocityFilter::Correct(const Vector6d& delta, const Matrix6d& posterior_pose_covariance,
                                 const Matrix6d& prior_pose_information) {
  const Matrix6d Pvp = covariance_.bottomLeftCorner<6, 6>();
  Matrix6d G;
  G.noalias() = Pvp.lazyProduct(prior_pose_information);
  velocity_.noalias() += G * delta;
  Matrix6d new_pvp;
  new_pvp.noalias() = G.lazyProduct(posterior_pose_covariance);
  // G (P_pp - P_pp+) G^T = (P_vp - G P_pp+) G^T, since G P_pp = P_vp.
  Matrix6d Pvv = covariance_.bottomRightCorner<6, 6>();
  Pvv.noalias() -= (Pvp - new_pvp).lazyProduct(G.transpose());
  covariance_.topLeftCorner<6, 6>() = 0.5 * (posterior_pose_covariance + posterior_pose_covariance.transpose());
  covariance_.bottomLeftCorner<6, 6>() = new_pvp;
  covariance_.topRightCorner<6, 6>() = new_pvp.transpose();
  covariance_.bottomRightCorner<6, 6>() = 0.5 * (Pvv + Pvv.transpose());
  cam_from_ref_ = ExpSE3(delta) * cam_from_ref_;
}

void PoseVelocityFilter::CorrectState(const Vector12d& delta, const Matrix12d& posterior_covariance) {
  covariance_ = 0.5 * (posterior_covariance + posterior_covariance.transpose());
  velocity_ += delta.tail<6>();
  cam_from_ref_ = ExpSE3(delta.head<6>()) * cam_from_ref_;
}

Matrix6d PoseVelocityFilter::MovePose(const Rigid3d& cam_from_ref, const Matrix6d& pose_covariance) {
  cam_from_ref_ = cam_from_ref;
  const Eigen::SelfAdjointEigenSolver<Matrix6d> prior(covariance_.topLeftCorner<6, 6>());
  const Eigen::SelfAdjointEigenSolver<Matrix6d> target(0.5 * (pose_covariance + pose_covariance.transpose()));
  const Vector6d lambda = prior.eigenvalues();
  Matrix6d t = Matrix6d::Zero();
  if (lambda.minCoeff() > 1e-12 * std::max(lambda.maxCoeff(), 1e-300)) {
    t = target.eigenvectors() * target.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() *
        target.eigenvectors().transpose() * prior.eigenvectors() * lambda.cwiseSqrt().cwiseInverse().asDiagonal() *
        prior.eigenvectors().transpose();
  }
  const Matrix6d p_pv = covariance_.topRightCorner<6, 6>();
  covariance_.topLeftCorner<6, 6>() = 0.5 * (pose_covariance + pose_covariance.transpose());
  covariance_.topRightCorner<6, 6>() = t * p_pv;
  covariance_.bottomLeftCorner<6, 6>() = covariance_.topRightCorner<6, 6>().transpose();
  return t;
}

void PoseVelocityFilter::Reseed(const Rigid3d& cam_from_ref, const Matrix6d& pose_covariance,
                                bool previous_pose_trusted) {
  cam_from_ref_ = cam_from_ref;
  velocity_ = previous_pose_trusted ? LogSE3(cam_from_ref * previous_cam_from_ref_.Inverse()) : Vector6d::Zero();
  covariance_.setZero();
  covariance_.topLeftCorner<6, 6>() = pose_covariance;
  covariance_.bottomRightCorner<6, 6>() = InitialVelocityCovariance();
}

void PoseVelocityFilter::DampVelocity(double factor) {
  velocity_ *= factor;
}

void PoseVelocityFilter::StartNewReferencePair() {
  cam_from_ref_ = Rigid3d();
  previous_cam_from_ref_ = Rigid3d();
  covariance_.topRows<6>().setZero();
  covariance_.leftCols<6>().setZero();
}

}  // namespace slt
