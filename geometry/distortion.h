// Radial-tangential lens distortion (Brown-Conrady with two radial and two tangential terms:
// EuRoC's "radial-tangential", OpenCV's first four coefficients [k1, k2, p1, p2]). With (x, y)
// the normalised coordinates of a point (z = 1 plane) and r^2 = x^2 + y^2:
//   x_d = x (1 + k1 r^2 + k2 r^4) + 2 p1 x y + p2 (r^2 + 2 x^2)
//   y_d = y (1 + k1 r^2 + k2 r^4) + p1 (r^2 + 2 y^2) + 2 p2 x y
// and the distorted pixel is (fx x_d + cx, fy y_d + cy). The renderer distorts with it
// (render/, docs/rendering.md) and the image front end removes it (frontend/stereo_rectification.h).
#pragma once

#include <Eigen/Core>
#include <array>

namespace slt {

using RadialTangential = std::array<double, 4>;  // [k1, k2, p1, p2]

inline bool IsZero(const RadialTangential& d) { return d[0] == 0.0 && d[1] == 0.0 && d[2] == 0.0 && d[3] == 0.0; }

Eigen::Vector2d DistortNormalized(const Eigen::Vector2d& xy, const RadialTangential& d);
// The inverse, by Newton's method from x = x_d (to 1e-12, or the best of 20 iterations where the
// model folds over, far outside any real lens's field of view).
Eigen::Vector2d UndistortNormalized(const Eigen::Vector2d& xy_distorted, const RadialTangential& d);

}  // namespace slt
