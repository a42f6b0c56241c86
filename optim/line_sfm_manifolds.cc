#include "optim/line_sfm_manifolds.h"

#include <cmath>

#include "geometry/se3.h"

namespace slt {
namespace {

using RowMajor12x6 = Eigen::Matrix<double, 12, 6, Eigen::RowMajor>;
using RowMajor6x12 = Eigen::Matrix<double, 6, 12, Eigen::RowMajor>;
using RowMajor6x4 = Eigen::Matrix<double, 6, 4, Eigen::RowMajor>;
using RowMajor4x6 = Eigen::Matrix<double, 4, 6, Eigen::RowMajor>;

// E = [e1 e2] of NormalPlaneBasis for the line's direction.
Eigen::Matrix<double, 3, 2> NormalPlaneMatrix(const PlueckerLine& line) {
  Eigen::Vector3d e1, e2;
  NormalPlaneBasis(line.direction, &e1, &e2);
  return (Eigen::Matrix<double, 3, 2>() << e1, e2).finished();
}

}  // namespace

void PoseToParameters(const Rigid3d& pose, double* parameters) {
  Eigen::Map<Eigen::Matrix3d>{parameters} = pose.rotation;  // column-major, as Eigen stores it
  Eigen::Map<Eigen::Vector3d>{parameters + 9} = pose.translation;
}

Rigid3d PoseFromParameters(const double* parameters) {
  return Rigid3d(Eigen::Map<const Eigen::Matrix3d>(parameters), Eigen::Map<const Eigen::Vector3d>(parameters + 9));
}

bool LineToParameters(const PlueckerLine& line, double* parameters) {
  const double norm = line.direction.norm();
  if (!(norm > 0.0) || !std::isfinite(norm) || !line.moment.allFinite()) return false;
  Eigen::Map<Eigen::Vector3d>{parameters} = line.moment / norm;
  Eigen::Map<Eigen::Vector3d>{parameters + 3} = line.direction / norm;
  return true;
}

PlueckerLine LineFromParameters(const double* parameters) {
  return {Eigen::Map<const Eigen::Vector3d>(parameters), Eigen::Map<const Eigen::Vector3d>(parameters + 3)};
}

void NormalPlaneBasis(const Eigen::Vector3d& d, Eigen::Vector3d* e1, Eigen::Vector3d* e2) {
  // Cross d with the coordinate axis it is least aligned with: |axis x d| >= sqrt(2/3).
  int axis = 0;
  d.cwiseAbs().minCoeff(&axis);
  *e1 = Eigen::Vector3d::Unit(axis).cross(d).normalized();
  *e2 = d.cross(*e1);
}

bool PoseManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  PoseToParameters(ExpSE3(Eigen::Map<const Vector6d>(delta)) * PoseFromParameters(x), x_plus_delta);
  return true;
}

bool PoseManifold::PlusJacobian(const double* x, double* jacobian) const {
  // Exp([v; w]) T = (R + [w]_x R, t + v + w x t) to first order: column j of R moves by
  // w x r_j = -[r_j]_x w, t by v - [t]_x w.
  const Rigid3d pose = PoseFromParameters(x);
  Eigen::Map<RowMajor12x6> j(jacobian);
  j.setZero();
  for (int c = 0; c < 3; ++c) j.block<3, 3>(3 * c, 3) = -Skew(pose.rotation.col(c));
  j.block<3, 3>(9, 0).setIdentity();
  j.block<3, 3>(9, 3) = -Skew(pose.translation);
  return true;
}

bool PoseManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  Eigen::Map<Vector6d>{y_minus_x} = LogSE3(PoseFromParameters(y) * PoseFromParameters(x).Inverse());
  return true;
}

bool PoseManifold::MinusJacobian(const double* x, double* jacobian) const {
  // y = x + dy: y x^-1 = (I + dR R^T, dt - dR R^T t) to first order. The rotation vector is the
  // axial part of dR R^T = sum_j dr_j r_j^T, i.e. w = 1/2 sum_j r_j x dr_j; v = dt - dR (R^T t).
  const Rigid3d pose = PoseFromParameters(x);
  const Eigen::Vector3d rt_t = pose.rotation.transpose() * pose.translation;
  Eigen::Map<RowMajor6x12> j(jacobian);
  j.setZero();
  for (int c = 0; c < 3; ++c) {
    j.block<3, 3>(0, 3 * c) = -rt_t(c) * Eigen::Matrix3d::Identity();
    j.block<3, 3>(3, 3 * c) = 0.5 * Skew(pose.rotation.col(c));
  }
  j.block<3, 3>(0, 9).setIdentity();
  return true;
}

bool LineManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  const PlueckerLine line = LineFromParameters(x);
  Eigen::Vector3d e1, e2;
  NormalPlaneBasis(line.direction, &e1, &e2);
  const Eigen::Matrix3d rotation = ExpSO3(delta[0] * e1 + delta[1] * e2);
  Eigen::Map<Eigen::Vector3d>{x_plus_delta} = rotation * (line.moment + delta[2] * e1 + delta[3] * e2);
  Eigen::Map<Eigen::Vector3d>{x_plus_delta + 3} = rotation * line.direction;
  return true;
}

bool LineManifold::PlusJacobian(const double* x, double* jacobian) const {
  // To first order d' = d + w x d, n' = n + E b + w x n with w = E a.
  const PlueckerLine line = LineFromParameters(x);
  const Eigen::Matrix<double, 3, 2> e = NormalPlaneMatrix(line);
  Eigen::Map<RowMajor6x4> j(jacobian);
  j.block<3, 2>(0, 0) = -Skew(line.moment) * e;
  j.block<3, 2>(0, 2) = e;
  j.block<3, 2>(3, 0) = -Skew(line.direction) * e;
  j.block<3, 2>(3, 2).setZero();
  return true;
}

Eigen::Matrix<double, kLineAmbientSize, 4> LineTangentBasis(const double* parameters) {
  RowMajor6x4 basis;
  LineManifold().PlusJacobian(parameters, basis.data());
  return basis;
}

Eigen::Matrix<double, 4, kLineAmbientSize> LineTangentFromAmbient(const Eigen::Matrix<double, kLineAmbientSize, 4>& basis) {
  return (basis.transpose() * basis).ldlt().solve(basis.transpose());
}

bool LineManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  const PlueckerLine from = LineFromParameters(x);
  PlueckerLine to = LineFromParameters(y);
  const double scale = 1.0 / to.direction.norm();
  to.moment *= scale;
  to.direction *= scale;
  // The shortest rotation taking d_x to d_y: about d_x x d_y, by the angle between them.
  const Eigen::Vector3d cross = from.direction.cross(to.direction);
  const double sine = cross.norm();
  const double angle = std::atan2(sine, from.direction.dot(to.direction));
  const Eigen::Vector3d w = sine > 0.0 ? Eigen::Vector3d(cross * (angle / sine)) : Eigen::Vector3d::Zero();
  Eigen::Vector3d e1, e2;
  NormalPlaneBasis(from.direction, &e1, &e2);
  const Eigen::Vector3d slide = ExpSO3(w).transpose() * to.moment - from.moment;
  y_minus_x[0] = e1.dot(w);
  y_minus_x[1] = e2.dot(w);
  y_minus_x[2] = e1.dot(slide);
  y_minus_x[3] = e2.dot(slide);
  return true;
}

bool LineManifold::MinusJacobian(const double* x, double* jacobian) const {
  // y = x + dy: the normalised direction moves by dd - d (d . dd), so w = d x dd, and
  // Exp(-w) n_y - n = dn - w x n - n (d . dd) to first order.
  const PlueckerLine line = LineFromParameters(x);
  const Eigen::Matrix<double, 3, 2> e = NormalPlaneMatrix(line);
  const Eigen::Matrix3d skew_d = Skew(line.direction);
  Eigen::Map<RowMajor4x6> j(jacobian);
  j.block<2, 3>(0, 0).setZero();
  j.block<2, 3>(0, 3) = e.transpose() * skew_d;
  j.block<2, 3>(2, 0) = e.transpose();
  j.block<2, 3>(2, 3) =
      e.transpose() * (Skew(line.moment) * skew_d - line.moment * line.direction.transpose());
  return true;
}

}  // namespace slt
