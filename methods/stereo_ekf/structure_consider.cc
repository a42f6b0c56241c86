#include "methods/stereo_ekf/structure_consider.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace slt {
namespace {

// An eigenvalue of the state covariance below this fraction of the largest is zero: the
// direction has no variance (to rounding).
constexpr double kRelativeZeroVariance = 1e-14;

}  // namespace

void StructureConsider::Reset(const FeatureModel& model) {
  const int n = model.NumStructures();
  cross_.assign(n, CrossCovariance::Zero());
  correlated_.assign(n, 0);
  versions_.resize(n);
  for (int s = 0; s < n; ++s) versions_[s] = model.StructureVersion(s);
}

void StructureConsider::Clear() {
  for (CrossCovariance& q : cross_) q.setZero();
  std::fill(correlated_.begin(), correlated_.end(), 0);
}

void StructureConsider::Sync(const FeatureModel& model) {
  for (int s = 0; s < size(); ++s) {
    const int version = model.StructureVersion(s);
    if (version == versions_[s]) continue;
    versions_[s] = version;
    cross_[s].setZero();
    correlated_[s] = 0;
  }
}

void StructureConsider::Predict(const Matrix12d& transition) {
  for (int s = 0; s < size(); ++s) {
    if (correlated_[s]) cross_[s] = transition * cross_[s];
  }
}

void StructureConsider::TransformPose(const Matrix6d& t) {
  for (int s = 0; s < size(); ++s) {
    if (correlated_[s]) cross_[s].topRows<6>() = t * cross_[s].topRows<6>();
  }
}

bool StructureConsider::Linearize(const FeatureModel& model, const WeightedFeature& feature, int index,
                                  const Rigid3d& cam_from_ref, double scale) {
  if (whitened_jacobian_.size() <= static_cast<size_t>(index)) {
    const size_t n = static_cast<size_t>(index) + 1;
    whitened_jacobian_.resize(n);
    structure_.resize(n);
    j_.resize(n);
    v_.resize(n);
  }
  FeatureModel::StructureJacobian& g = whitened_jacobian_[index];
  const int s = model.StructureOf(index);
  if (s < 0 || s >= size() || !model.EvaluateStructureJacobian(index, cam_from_ref, &g) || !g.allFinite()) {
    return false;
  }
  g *= scale;
  ForwardSubstitute4(feature.sqrt_covariance, &g);
  structure_[index] = s;
  return true;
}

bool StructureConsider::Solve(const std::vector<WeightedFeature>& features, const std::vector<int>& inliers,
                              const Matrix12d& covariance, const Vector6d& delta_k, Vector12d* delta,
                              Matrix12d* posterior) {
  // In coordinates where the prior is N(0, I): e = L e~ (P = L L^T), Q~_s = L^-1 Q_s.
  // In coordinates where the prior is N(0, I): e = L e~, L = U diag(sqrt(lambda)) from the
  // eigen-decomposition of P, which may be singular (just after a start or a new reference pair
  // the pose error is the velocity's). Directions of (numerically) zero variance get no
  // coordinate: Q~ = L^+ Q, and Q has no component there while P >= Q Q^T.
  const Eigen::SelfAdjointEigenSolver<Matrix12d> eigen(covariance);
  if (eigen.info() != Eigen::Success) return false;
  const Vector12d lambda = eigen.eigenvalues();
  if (!(lambda(11) > 0.0)) return false;
  Vector12d sqrt_lambda, inverse_sqrt_lambda;
  for (int k = 0; k < 12; ++k) {
    const bool zero = lambda(k) <= kRelativeZeroVariance * lambda(11);
    sqrt_lambda(k) = zero ? 0.0 : std::sqrt(lambda(k));
    inverse_sqrt_lambda(k) = zero ? 0.0 : 1.0 / sqrt_lambda(k);
  }
  lower_ = eigen.eigenvectors() * sqrt_lambda.asDiagonal();
  lower_inverse_ = inverse_sqrt_lambda.asDiagonal() * eigen.eigenvectors().transpose();
  const Eigen::Matrix<double, 6, 12> lower_pose = lower_.topRows<6>();
  Matrix12d ata = Matrix12d::Zero(), atv = Matrix12d::Zero(), vtv = Matrix12d::Zero();
  Matrix12d atj = Matrix12d::Zero(), vtj = Matrix12d::Zero();
  Vector12d at_nu = Vector12d::Zero(), vt_nu = Vector12d::Zero();
  for (int i : inliers) {
    const WeightedFeature& f = features[i];
    const FeatureModel::StructureJacobian& g = whitened_jacobian_[i];
    const Eigen::Matrix<double, 12, FeatureModel::kStructureNoiseSize> q = lower_inverse_ * cross_[structure_[i]];
    Eigen::Matrix<double, 4, 12>& j = j_[i];
    j.noalias() = f.whitened_jacobian * lower_pose;
    Eigen::Matrix<double, 4, 12>& v = v_[i];
    v.noalias() = g * q.transpose();
    const Eigen::Matrix<double, 4, 12> a = j + v;
    const Eigen::Vector4d nu = -(f.whitened_residual - f.whitened_jacobian * delta_k);
    ata.noalias() += a.transpose() * a;
    atv.noalias() += a.transpose() * v;
    vtv.noalias() += v.transpose() * v;
    atj.noalias() += a.transpose() * j;
    vtj.noalias() += v.transpose() * j;
    at_nu.noalias() += a.transpose() * nu;
    vt_nu.noalias() += v.transpose() * nu;
  }
  // W = I - V V^T, W^-1 = I + V N^-1 V^T with N = I - V^T V (positive definite while the
  // cross-covariances are consistent, P >= Q Q^T).
  const Eigen::LLT<Matrix12d> n_llt(Matrix12d::Identity() - vtv);
  if (n_llt.info() != Eigen::Success) return false;
  const Matrix12d atv_ninv = n_llt.solve(atv.transpose()).transpose();  // A^T V N^-1
  Matrix12d information = Matrix12d::Identity() + ata;
  information.noalias() += atv_ninv * atv.transpose();
  information_llt_.compute(information);
  if (information_llt_.info() != Eigen::Success) return false;
  atv_ninv_ = atv_ninv;
  const Vector12d normalized = information_llt_.solve(at_nu + atv_ninv * vt_nu);
  *delta = lower_ * normalized;
  const Matrix12d normalized_posterior = information_llt_.solve(Matrix12d::Identity());
  *posterior = lower_ * normalized_posterior * lower_.transpose();
  kj_ = information_llt_.solve(atj + atv_ninv * vtj);  // K~ J^
  return delta->allFinite() && posterior->allFinite();
}

void StructureConsider::Commit(const std::vector<int>& inliers) {
  // Q~_s+ = Q~_s - (K~ J^) Q~_s - K~_i G~_i, K~_i = Lambda^-1 (A_i^T + A^T V N^-1 V_i^T), all
  // from the cross-covariances before the update; then Q_s+ = L Q~_s+.
  // (A structure never measured since its Q was zeroed keeps Q = 0: skipped.)
  for (int s = 0; s < size(); ++s) {
    if (!correlated_[s]) continue;
    CrossCovariance& q = cross_[s];
    q = lower_inverse_ * q;
    q -= kj_ * q;
  }
  for (int i : inliers) {
    Eigen::Matrix<double, 12, 4> k = (j_[i] + v_[i]).transpose();
    k.noalias() += atv_ninv_ * v_[i].transpose();
    const int s = structure_[i];
    cross_[s].noalias() -= information_llt_.solve(k) * whitened_jacobian_[i];
    correlated_[s] = 1;
  }
  for (int s = 0; s < size(); ++s) {
    if (correlated_[s]) cross_[s] = lower_ * cross_[s];
  }
}

}  // namespace slt
