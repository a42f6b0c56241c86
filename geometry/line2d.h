// Homogeneous 2-D lines: construction from segments, normalisation with the intrinsics
// (paper eq. 6-7), the slope/polar-radius form (replacing the printed eq. 8-9, see
// docs/derivations.md) and endpoint-to-line distances, each with its Jacobian.
//
// A line l = (a, b, c) holds the points x with a x + b y + c = 0. Lines are defined up to a
// non-zero scale, including its sign; functions here never assume a particular scale unless
// they say so.
#pragma once

#include <Eigen/Core>

#include "geometry/camera.h"

namespace slt {

using Segment2d = Eigen::Vector4d;  // [u1 v1 u2 v2]

inline Eigen::Vector3d Homogeneous(const Eigen::Vector2d& p) { return {p.x(), p.y(), 1.0}; }

inline double SegmentLength(const Segment2d& s) { return (s.tail<2>() - s.head<2>()).norm(); }

// l = [a; 1] x [b; 1]: the line through two points, with its 3x4 Jacobian with respect to
// [a; b] when asked for.
Eigen::Vector3d LineThroughPoints(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                  Eigen::Matrix<double, 3, 4>* d_points = nullptr);
inline Eigen::Vector3d LineFromSegment(const Segment2d& s,
                                       Eigen::Matrix<double, 3, 4>* d_segment = nullptr) {
  return LineThroughPoints(s.head<2>(), s.tail<2>(), d_segment);
}

// Paper eq. 6-7: the line in normalised image coordinates, K^T l (eq. 6 divides this by f^2,
// the same line). The inverse map is K^-T l.
Eigen::Vector3d NormalizedLineFromPixelLine(const PinholeCamera& camera, const Eigen::Vector3d& line);
Eigen::Vector3d PixelLineFromNormalizedLine(const PinholeCamera& camera, const Eigen::Vector3d& line);
// K^-T as a matrix, for chaining Jacobians.
Eigen::Matrix3d PixelFromNormalizedLineMatrix(const PinholeCamera& camera);

// Scales a line so that a^2 + b^2 = 1 (sign kept).
Eigen::Vector3d UnitNormalLine(const Eigen::Vector3d& line);

// Signed distance (a x + b y + c) / sqrt(a^2 + b^2), with gradients with respect to the line
// and to the point when asked for.
double SignedDistance(const Eigen::Vector3d& line, const Eigen::Vector2d& point,
                      Eigen::Matrix<double, 1, 3>* d_line = nullptr,
                      Eigen::Matrix<double, 1, 2>* d_point = nullptr);

// The slope/polar-radius form used by the paper's residual: x cos(theta) + y sin(theta) = lambda
// with theta = atan2(b, a) and lambda = -c / sqrt(a^2 + b^2). Defined for every line with
// (a, b) != 0: there is no singular direction (the printed eq. 9 divides by zero, docs/derivations.md Sec. 2).
Eigen::Vector2d ThetaLambdaFromLine(const Eigen::Vector3d& line,
                                    Eigen::Matrix<double, 2, 3>* d_line = nullptr);

// Residual [theta_m - theta_p; lambda_m - lambda_p] between a measured and a predicted line.
// The predicted line's sign is first chosen so that its normal agrees with the measured one
// (lines are unoriented), and the angle difference is wrapped to (-pi, pi]. d_predicted is
// the Jacobian of the residual with respect to the predicted line as given (sign included).
Eigen::Vector2d ThetaLambdaResidual(const Eigen::Vector3d& measured, const Eigen::Vector3d& predicted,
                                    Eigen::Matrix<double, 2, 3>* d_predicted = nullptr);

// Wraps an angle to (-pi, pi].
double WrapAngle(double angle);

}  // namespace slt
