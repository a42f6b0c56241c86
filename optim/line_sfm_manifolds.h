// The two Ceres manifolds of the Taylor & Kriegman baseline (taylor_line_sfm.h): camera poses on
// SE(3) and 3-D lines with four degrees of freedom.
//
// Pose: the left camera's cam_from_world, stored as 12 numbers [R column-major (9); t (3)], with
// the project's perturbation (docs/conventions.md):
//     Plus(T, delta) = ExpSE3(delta) * T,   delta = [v; w] (paper eq. 3-5),
// so the tangent space is the current camera frame and the twist ordering is the trackers'. The
// ambient form is the matrix itself (not a quaternion) because the residual is linear in R and
// t: the cost function's ambient Jacobian is then exact and cheap (taylor_segment_cost.h), and
// Ceres chains it with PlusJacobian. (A quaternion would need dR/dq in every residual.)
//
// Line: Pluecker coordinates [n; d] (moment, direction; n = p x d, geometry/plucker.h) scaled
// so that |d| = 1 -- then n = p x d with p the point of the line closest to the origin, and
// |n| its distance. This is Taylor & Kriegman's representation (a unit direction and the point
// of the line closest to the origin; PAMI 1995), written with the moment, and the update
//     d' = Exp(w) d,   n' = Exp(w) (n + E b),   w = E a,   E = [e1 e2] a basis of d's normal plane,
// tangent [a (2, rad); b (2, m)]. Exp(w) rotates the line about the origin and E b slides it
// within the plane normal to its direction; n' stays orthogonal to d'.
// Why not Bartoli & Sturm's orthonormal (U, W) update (CVIU 2005): it is minimal too, but
// where the moment vanishes (a line through the world origin, which is the first camera's
// centre) the first column of U is undefined and the update loses a rank; Taylor's form is
// regular for every line with a direction, and its tangent is in radians and metres like the
// pose's, which keeps the trust region's scaling even.
#pragma once

#include <ceres/manifold.h>
#include <ceres/problem.h>

#include <Eigen/Core>

#include "geometry/plucker.h"
#include "geometry/rigid3.h"

namespace slt {

constexpr int kPoseAmbientSize = 12;
constexpr int kLineAmbientSize = 6;

// Options of a problem that owns none of its cost functions, losses and manifolds: the line
// bundle adjustments keep them and reuse them from solve to solve.
inline ceres::Problem::Options BorrowingProblemOptions() {
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  return options;
}

// [R column-major; t] <-> Rigid3d.
void PoseToParameters(const Rigid3d& pose, double* parameters);
Rigid3d PoseFromParameters(const double* parameters);

// [n; d] with |d| = 1 (the sign is kept) <-> PlueckerLine. Returns false for a line without a
// direction (|d| = 0 or not finite), leaving `parameters` untouched.
bool LineToParameters(const PlueckerLine& line, double* parameters);
PlueckerLine LineFromParameters(const double* parameters);

// The LineManifold's tangent basis at `parameters`, B = d Plus(x, delta) / d delta at delta = 0
// (6 x 4), and its left pseudo-inverse B^+ = (B^T B)^-1 B^T, which takes a change of [n; d] to
// the tangent coordinates a line's covariance is kept in (B is not orthonormal where n != 0).
Eigen::Matrix<double, kLineAmbientSize, 4> LineTangentBasis(const double* parameters);
Eigen::Matrix<double, 4, kLineAmbientSize> LineTangentFromAmbient(const Eigen::Matrix<double, kLineAmbientSize, 4>& basis);

// e1, e2 with (e1, e2, d) a right-handed orthonormal basis, for a unit d. A fixed function of d
// (so that Plus and PlusJacobian at one point agree); not continuous over the sphere, which a
// tangent basis does not need to be.
void NormalPlaneBasis(const Eigen::Vector3d& d, Eigen::Vector3d* e1, Eigen::Vector3d* e2);

// cam_from_world <- ExpSE3(delta) * cam_from_world; Minus(y, x) = LogSE3(y * x^-1).
class PoseManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return kPoseAmbientSize; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

// Taylor's line update above. The manifold is that of oriented lines: [n; d] and [-n; -d] are
// two points of it (the same image line, the residuals do not tell them apart), and Minus
// between them is a half turn. Minus(y, x) normalises y to |d| = 1 first.
class LineManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return kLineAmbientSize; }
  int TangentSize() const override { return 4; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

}  // namespace slt
