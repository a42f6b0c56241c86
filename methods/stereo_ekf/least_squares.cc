#include "methods/stereo_ekf/least_squares.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>

namespace slt {

bool SpdSolver6::Compute(const Matrix6d& a) {
  for (int j = 0; j < 6; ++j) {
    double d = a(j, j);
    for (int k = 0; k < j; ++k) d -= lower_(j, k) * lower_(j, k);
    if (!(d > 0.0)) return false;
    lower_(j, j) = std::sqrt(d);
    inverse_diagonal_(j) = 1.0 / lower_(j, j);
    for (int i = j + 1; i < 6; ++i) {
      double s = a(i, j);
      for (int k = 0; k < j; ++k) s -= lower_(i, k) * lower_(j, k);
      lower_(i, j) = s * inverse_diagonal_(j);
    }
  }
  return true;
}

Vector6d SpdSolver6::Solve(const Vector6d& b) const {
  Vector6d y;
  for (int i = 0; i < 6; ++i) {  // L y = b
    double s = b(i);
    for (int k = 0; k < i; ++k) s -= lower_(i, k) * y(k);
    y(i) = s * inverse_diagonal_(i);
  }
  for (int i = 5; i >= 0; --i) {  // L^T x = y
    double s = y(i);
    for (int k = i + 1; k < 6; ++k) s -= lower_(k, i) * y(k);
    y(i) = s * inverse_diagonal_(i);
  }
  return y;
}

double SpdSolver6::SquaredNorm(const Vector6d& v) const {
  double sum = 0.0;
  for (int j = 0; j < 6; ++j) {  // (L^T v)_j = sum_{i >= j} L(i, j) v(i)
    double s = 0.0;
    for (int i = j; i < 6; ++i) s += lower_(i, j) * v(i);
    sum += s * s;
  }
  return sum;
}

Matrix6d SpdSolver6::Inverse() const {
  // M = L^-1 (lower triangular), then a^-1 = M^T M.
  Matrix6d m = Matrix6d::Zero();
  for (int j = 0; j < 6; ++j) {
    m(j, j) = inverse_diagonal_(j);
    for (int i = j + 1; i < 6; ++i) {
      double s = 0.0;
      for (int k = j; k < i; ++k) s -= lower_(i, k) * m(k, j);
      m(i, j) = s * inverse_diagonal_(i);
    }
  }
  Matrix6d inverse;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j <= i; ++j) {
      double s = 0.0;
      for (int k = i; k < 6; ++k) s += m(k, i) * m(k, j);
      inverse(i, j) = s;
      inverse(j, i) = s;
    }
  }
  return inverse;
}

bool InvertSpd6(const Matrix6d& a, Matrix6d* inverse) {
  SpdSolver6 solver;
  if (!solver.Compute(a)) return false;
  *inverse = solver.Inverse();
  return true;
}

bool CholeskyLower4(const Eigen::Matrix4d& a, Eigen::Matrix4d* lower) {
  Eigen::Matrix4d& l = *lower;
  l.setZero();
  for (int j = 0; j < 4; ++j) {
    double d = a(j, j);
    for (int k = 0; k < j; ++k) d -= l(j, k) * l(j, k);
    if (!(d > 0.0)) return false;
    l(j, j) = std::sqrt(d);
    for (int i = j + 1; i < 4; ++i) {
      double s = a(i, j);
      for (int k = 0; k < j; ++k) s -= l(i, k) * l(j, k);
      l(i, j) = s / l(j, j);
    }
  }
  return true;
}

bool WeightedFeature::FactorCovariance() { return CholeskyLower4(block.covariance, &sqrt_covariance); }

void WeightedFeature::Whiten(const Eigen::Vector4d& residual, const Eigen::Matrix<double, 4, 6>& jacobian,
                             Eigen::Vector4d* rw, Eigen::Matrix<double, 4, 6>* jw) const {
  Eigen::Matrix<double, 4, 7, Eigen::RowMajor> b;  // rows contiguous for the substitution
  b.col(0) = residual;
  b.rightCols<6>() = jacobian;
  ForwardSubstitute4(sqrt_covariance, &b);
  *rw = b.col(0);
  *jw = b.rightCols<6>();
}

double WeightedFeature::WhitenedSquaredNorm(const Eigen::Vector4d& residual) const {
  Eigen::Matrix<double, 4, 1> b = residual;
  ForwardSubstitute4(sqrt_covariance, &b);
  return b.squaredNorm();
}

bool EvaluateForWhitener(const FeatureModel& model, const WeightedFeature& feature, int index,
                         const Rigid3d& cam_from_ref, FeatureBlock* block) {
  return model.Evaluate(index, cam_from_ref, false, block) && block->RestrictTo(feature.block.measured_rows) &&
         block->residual.allFinite() && block->jacobian.allFinite();
}

bool WhitenedCost(const FeatureModel& model, const WeightedFeature& feature, int index,
                  const Rigid3d& cam_from_ref, double* cost) {
  FeatureBlock block;
  if (!EvaluateForWhitener(model, feature, index, cam_from_ref, &block)) return false;
  *cost = feature.WhitenedSquaredNorm(block.residual);
  return std::isfinite(*cost);
}

bool RefinePose(const FeatureModel& model, const std::vector<WeightedFeature>& features,
                const int* indices, int count, int iterations, Rigid3d* cam_from_ref,
                Matrix6d* information, double max_sigma) {
  Rigid3d pose = *cam_from_ref;
  FeatureBlock block;
  NormalEquations ne;
  for (int it = 0; it <= iterations; ++it) {
    ne = NormalEquations();
    for (int k = 0; k < count; ++k) {
      const int i = indices[k];
      if (!EvaluateForWhitener(model, features[i], i, pose, &block)) return false;
      Eigen::Vector4d rw;
      Eigen::Matrix<double, 4, 6> jw;
      features[i].Whiten(block.residual, block.jacobian, &rw, &jw);
      ne.AddWhitened(rw, jw);
    }
    if (it == iterations) break;  // the last pass only evaluates the information at the solution
    // A singular Hessian is allowed: Yu's minimal sample, two points, never observes the
    // rotation about the line through them. LDLT's zero pivot meets a zero gradient component
    // there, so that direction does not move; the others are solved. A direction observed barely
    // moves by the gradient's noise over a small pivot: max_sigma keeps it too (header).
    // (Rejecting such samples was measured: RANSAC over points then fails.)
    Vector6d step;
    if (max_sigma > 0.0) {
      const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(ne.FullHessian());
      if (eigen.info() != Eigen::Success) return false;
      step.setZero();
      for (int d = 0; d < 6; ++d) {
        const double lambda = eigen.eigenvalues()(d);
        if (lambda * max_sigma * max_sigma < 1.0) continue;  // determined worse than max_sigma
        step -= eigen.eigenvectors().col(d) * (eigen.eigenvectors().col(d).dot(ne.gradient) / lambda);
      }
    } else {
      const Eigen::LDLT<Matrix6d> ldlt(ne.FullHessian());
      if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
      step = -ldlt.solve(ne.gradient);
    }
    // Diverging: half a radian, or a metre, in one step of a per-frame pose.
    if (!step.allFinite() || step.tail<3>().norm() > 0.5 || step.head<3>().norm() > 1.0) return false;
    pose = ExpSE3(step) * pose;
    if (step.norm() < 1e-12) {
      it = iterations - 1;  // converged: one more pass for the information
    }
  }
  *cam_from_ref = pose;
  *information = ne.FullHessian();
  return information->allFinite();
}

}  // namespace slt
