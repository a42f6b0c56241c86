// Whitened residual blocks and Gauss-Newton on the pose, shared by the EKF update and the
// robust (RANSAC) solve.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "geometry/se3.h"
#include "methods/stereo_ekf/feature_model.h"

namespace slt {

// One feature of the current frame, evaluated at a linearisation point.
struct WeightedFeature {
  FeatureBlock block;
  // L with R = L L^T: whitening is L^-1 (r, J), by forward substitution.
  Eigen::Matrix4d sqrt_covariance;
  // Innovation r^T (J P J^T + R)^-1 r at the prediction, or its upper bound r^T R^-1 r when
  // that bound is already inside the gate.
  double nis = 0.0;
  // Whitened residual and Jacobian at the last linearisation (first: the prediction), for the
  // update and the per-feature posterior cost |rw + jw (d* - d_k)|^2.
  Eigen::Vector4d whitened_residual;
  Eigen::Matrix<double, 4, 6> whitened_jacobian;

  // Sets sqrt_covariance from block.covariance; false if it is not positive definite.
  bool FactorCovariance();
  // Whitens a residual and Jacobian with this feature's covariance.
  void Whiten(const Eigen::Vector4d& residual, const Eigen::Matrix<double, 4, 6>& jacobian,
              Eigen::Vector4d* rw, Eigen::Matrix<double, 4, 6>* jw) const;
  double WhitenedSquaredNorm(const Eigen::Vector4d& residual) const;
};

// Cholesky factor of a 4x4 symmetric positive-definite matrix, unrolled for the size; false if
// not positive definite.
bool CholeskyLower4(const Eigen::Matrix4d& a, Eigen::Matrix4d* lower);
// Solves L X = B in place (L lower triangular 4x4, B 4xN), unrolled over the rows.
template <int N, int Options>
void ForwardSubstitute4(const Eigen::Matrix4d& l, Eigen::Matrix<double, 4, N, Options>* b) {
  Eigen::Matrix<double, 4, N, Options>& x = *b;
  x.row(0) *= 1.0 / l(0, 0);
  x.row(1) = (x.row(1) - l(1, 0) * x.row(0)) * (1.0 / l(1, 1));
  x.row(2) = (x.row(2) - l(2, 0) * x.row(0) - l(2, 1) * x.row(1)) * (1.0 / l(2, 2));
  x.row(3) = (x.row(3) - l(3, 0) * x.row(0) - l(3, 1) * x.row(1) - l(3, 2) * x.row(2)) * (1.0 / l(3, 3));
}

// Sums of J^T W^T W J, J^T W^T W r and r^T W^T W r over blocks.
struct NormalEquations {
  Matrix6d hessian = Matrix6d::Zero();
  Vector6d gradient = Vector6d::Zero();
  double cost = 0.0;

  void AddWhitened(const Eigen::Vector4d& rw, const Eigen::Matrix<double, 4, 6>& jw) {
    // Upper triangle only (21 of 36 entries); FullHessian() mirrors it.
    for (int c = 0; c < 6; ++c) {
      for (int r = 0; r <= c; ++r) hessian(r, c) += jw.col(r).dot(jw.col(c));
    }
    gradient.noalias() += jw.transpose() * rw;
    cost += rw.squaredNorm();
  }
  Matrix6d FullHessian() const { return hessian.selfadjointView<Eigen::Upper>(); }
};

// Cholesky factorisation of a symmetric positive-definite 6x6 matrix, with solves and the
// inverse written out for the fixed size (Eigen's LDLT/LLT with a matrix right-hand side takes
// a generic blocked path that costs several times more at this size).
class SpdSolver6 {
 public:
  // False if `a` is not positive definite.
  bool Compute(const Matrix6d& a);
  Vector6d Solve(const Vector6d& b) const;
  Matrix6d Inverse() const;
  // v^T a v = |L^T v|^2 (the squared Mahalanobis length of v when a is an information matrix).
  double SquaredNorm(const Vector6d& v) const;
  // The lower-triangular factor L (a = L L^T); only the lower triangle is meaningful.
  Matrix6d lower() const { return lower_.triangularView<Eigen::Lower>(); }

 private:
  Matrix6d lower_;
  Vector6d inverse_diagonal_;
};

// Convenience: the inverse, false if not positive definite.
bool InvertSpd6(const Matrix6d& a, Matrix6d* inverse);

// Evaluates feature `index` at `cam_from_ref` (another pose than the one `feature` was whitened
// at) into `block`, on the rows `feature`'s whitener was built for. False when it is degenerate
// or not finite there, or no longer measures one of those rows (FeatureBlock::RestrictTo).
bool EvaluateForWhitener(const FeatureModel& model, const WeightedFeature& feature, int index,
                         const Rigid3d& cam_from_ref, FeatureBlock* block);

// Squared whitened residual of feature `index` at `cam_from_ref` (false where
// EvaluateForWhitener is).
bool WhitenedCost(const FeatureModel& model, const WeightedFeature& feature, int index,
                  const Rigid3d& cam_from_ref, double* cost);

// Gauss-Newton without prior on the features `indices`, starting at *cam_from_ref, whitened with
// each feature's covariance. On success returns true and sets *cam_from_ref and *information (the
// Hessian H = J^T R^-1 J at the solution, possibly singular: a direction the features do not
// observe is left where it started). Fails when a step diverges or a feature becomes degenerate
// (or loses one of its measured rows). iterations = 0 only evaluates the information at
// *cam_from_ref.
//
// max_sigma = 0 solves every direction (LDLT): a direction observed exactly not at all has a zero
// pivot and a zero gradient and stays, but one observed barely (the noise of the features only:
// the height seen by vertical lines) has a small pivot that divides the gradient's noise, and
// the pose moves along it by anything. max_sigma > 0 steps only along the eigenvectors of H
// whose standard deviation 1 / sqrt(lambda) is at most max_sigma (metres and radians alike:
// the twist mixes both); the others keep the start's value (docs/long_sequences.md).
bool RefinePose(const FeatureModel& model, const std::vector<WeightedFeature>& features,
                const int* indices, int count, int iterations, Rigid3d* cam_from_ref,
                Matrix6d* information, double max_sigma = 0.0);

}  // namespace slt
