#include "geometry/distortion.h"

#include <Eigen/Dense>
#include <limits>

namespace slt {
namespace {

// The distorted point and its Jacobian with respect to (x, y).
Eigen::Vector2d Distort(const Eigen::Vector2d& p, const RadialTangential& d, Eigen::Matrix2d* jacobian) {
  const double x = p.x(), y = p.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + d[0] * r2 + d[1] * r2 * r2;
  const double k1 = d[0], k2 = d[1], p1 = d[2], p2 = d[3];
  if (jacobian != nullptr) {
    const double dradial_dr2 = k1 + 2.0 * k2 * r2;
    // d(r2)/dx = 2x, d(r2)/dy = 2y.
    (*jacobian)(0, 0) = radial + x * dradial_dr2 * 2.0 * x + 2.0 * p1 * y + p2 * 6.0 * x;
    (*jacobian)(0, 1) = x * dradial_dr2 * 2.0 * y + 2.0 * p1 * x + p2 * 2.0 * y;
    (*jacobian)(1, 0) = y * dradial_dr2 * 2.0 * x + p1 * 2.0 * x + 2.0 * p2 * y;
    (*jacobian)(1, 1) = radial + y * dradial_dr2 * 2.0 * y + p1 * 6.0 * y + 2.0 * p2 * x;
  }
  return {x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
          y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y};
}

}  // namespace

Eigen::Vector2d DistortNormalized(const Eigen::Vector2d& xy, const RadialTangential& d) {
  return Distort(xy, d, nullptr);
}

Eigen::Vector2d UndistortNormalized(const Eigen::Vector2d& xy_distorted, const RadialTangential& d) {
  Eigen::Vector2d x = xy_distorted, best = x;
  double best_residual = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 20; ++i) {
    Eigen::Matrix2d jacobian;
    const Eigen::Vector2d residual = Distort(x, d, &jacobian) - xy_distorted;
    const double norm = residual.norm();
    if (norm < best_residual) {
      best_residual = norm;
      best = x;
    }
    if (norm < 1e-12) break;
    x -= jacobian.partialPivLu().solve(residual);
  }
  return best;
}

}  // namespace slt
