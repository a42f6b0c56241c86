// The twist motion model (paper Sec. 2, eq. 3-5) and the SE(3) exponential map with its
// Jacobians.
//
// A twist is xi = [v; w] = [x y z alpha beta gamma]^T (eq. 3): translation part first, then
// rotation about the x, y, z axes. Its 4x4 form is Hat(xi) (eq. 4) and the rigid motion it
// generates is exp(Hat(xi)) (eq. 5), evaluated here in closed form (Rodrigues), not by the
// truncated series. Jacobians follow Barfoot, "State Estimation for Robotics", Sec. 7.1:
//   Exp(xi + d) ~= Exp(J_l(xi) d) Exp(xi) ~= Exp(xi) Exp(J_r(xi) d).
#pragma once

#include <Eigen/Core>

#include "geometry/rigid3.h"

namespace slt {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
// Jacobians with respect to a twist.
using Matrix26d = Eigen::Matrix<double, 2, 6>;
using Matrix36d = Eigen::Matrix<double, 3, 6>;
using Matrix46d = Eigen::Matrix<double, 4, 6>;

// [w]_x, so that Skew(w) * u = w.cross(u). Inline: it sits in every per-line Jacobian.
inline Eigen::Matrix3d Skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return m;
}

// SO(3) exponential (Rodrigues) and logarithm; the log returns the axis-angle vector with
// angle in [0, pi].
Eigen::Matrix3d ExpSO3(const Eigen::Vector3d& w);
Eigen::Vector3d LogSO3(const Eigen::Matrix3d& rotation);

// SO(3) left Jacobian J(w) and its inverse: ExpSO3(w + d) ~= ExpSO3(J(w) d) ExpSO3(w).
Eigen::Matrix3d LeftJacobianSO3(const Eigen::Vector3d& w);
Eigen::Matrix3d LeftJacobianInverseSO3(const Eigen::Vector3d& w);

// Paper eq. 4: the 4x4 matrix of a twist.
Eigen::Matrix4d Hat(const Vector6d& xi);

// Paper eq. 5: the rigid motion exp(Hat(xi)), in closed form.
Rigid3d ExpSE3(const Vector6d& xi);
// Rotation angle of R in radians, in [0, pi], robust near 0 and pi.
double RotationAngle(const Eigen::Matrix3d& rotation);
// Inverse of ExpSE3 for rotation angles below pi.
Vector6d LogSE3(const Rigid3d& transform);

// Paper eq. 12: the first-order approximation I + Hat(xi), re-orthonormalised so that the
// result is a rigid motion (the paper's form is not; the projection keeps poses valid).
Rigid3d FirstOrderSE3(const Vector6d& xi);

// Adjoint: T Exp(xi) T^-1 = Exp(Adjoint(T) xi); for xi = [v; w], [[R, [t]_x R], [0, R]].
Matrix6d Adjoint(const Rigid3d& transform);

// The SE(3) left Jacobian (Barfoot eq. 7.83-7.86 with the [v; w] ordering): the exact value
// the first-order form below is checked against.
Matrix6d LeftJacobianSE3(const Vector6d& xi);
// I + ad(xi) / 2: J_l to first order (error O(|xi|^2)), for per-frame twists in hot loops where
// the Jacobian only sets a convergence rate or a covariance to that order.
Matrix6d LeftJacobianSE3FirstOrder(const Vector6d& xi);

}  // namespace slt
