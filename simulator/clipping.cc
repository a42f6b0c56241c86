#include "simulator/clipping.h"

#include <algorithm>

namespace slt {

bool ClipSegmentToDepth(double min_depth, Eigen::Vector3d* p, Eigen::Vector3d* q) {
  const bool p_in = p->z() >= min_depth, q_in = q->z() >= min_depth;
  if (p_in && q_in) return true;
  if (!p_in && !q_in) return false;
  Eigen::Vector3d& behind = p_in ? *q : *p;
  const Eigen::Vector3d& front = p_in ? *p : *q;
  const double t = (min_depth - front.z()) / (behind.z() - front.z());
  behind = front + t * (behind - front);
  behind.z() = min_depth;  // exactly on the plane despite rounding
  return true;
}

bool ClipSegmentToImage(int width, int height, Eigen::Vector2d* a, Eigen::Vector2d* b) {
  const Eigen::Vector2d lo(0.0, 0.0), hi(width - 1.0, height - 1.0);
  const Eigen::Vector2d d = *b - *a;
  double t0 = 0.0, t1 = 1.0;
  // Each image side is a constraint p t <= q on the point a + t d; [t0, t1] shrinks to the
  // part of [0, 1] that meets all four.
  const auto clip = [&](double p, double q) {
    if (p == 0.0) return q >= 0.0;  // parallel to this boundary: inside or out entirely
    const double r = q / p;
    if (p < 0.0) {
      if (r > t1) return false;
      t0 = std::max(t0, r);
    } else {
      if (r < t0) return false;
      t1 = std::min(t1, r);
    }
    return true;
  };
  if (!clip(-d.x(), a->x() - lo.x()) || !clip(d.x(), hi.x() - a->x()) || !clip(-d.y(), a->y() - lo.y()) ||
      !clip(d.y(), hi.y() - a->y())) {
    return false;
  }
  const Eigen::Vector2d start = *a;
  // Clamping only removes rounding (1e-13 px) from points computed on the boundary.
  *a = (start + t0 * d).cwiseMax(lo).cwiseMin(hi);
  *b = (start + t1 * d).cwiseMax(lo).cwiseMin(hi);
  return true;
}

}  // namespace slt
