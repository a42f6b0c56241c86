// Noise-free primitive configurations and stereo lines for the tests and the benchmark of the
// three-line solvers (three_line_solver.h), and the choice of scene lines without a
// configuration for the tracker's tests.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "geometry/plucker.h"
#include "geometry/se3.h"
#include "methods/elqursh_three_line/three_line_solver.h"

namespace slt {
namespace three_line_test {

inline const Rigid3d kRightFromLeft(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.1, 0.0, 0.0));

struct Line3 {
  Eigen::Vector3d p, q;
};

// The normalised image line of a 3-D segment (given in frame a) in the camera cam_from_a.
inline Eigen::Vector3d ImageLine(const Rigid3d& cam_from_a, const Line3& line) {
  return (cam_from_a * line.p).cross(cam_from_a * line.q);
}

inline Eigen::Vector3d RandomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
}

inline Eigen::Vector3d PointInFront(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-0.2, 0.2), z(0.4, 0.7);
  return {u(rng), u(rng), z(rng)};
}

// The paper protocol's motion between frames, a few times larger.
inline Rigid3d RandomMotion(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> t(-0.03, 0.03), w(-0.06, 0.06);
  Vector6d xi;
  xi << t(rng), t(rng), t(rng), w(rng), w(rng), w(rng);
  return ExpSE3(xi);
}

// Two parallel lines and one orthogonal to them, each 0.2 m long, about 0.5 m in front.
inline std::array<Line3, 3> RandomPrimitiveConfiguration(std::mt19937_64& rng) {
  const Eigen::Vector3d d1 = RandomUnit(rng);
  const Eigen::Vector3d d2 = d1.cross(RandomUnit(rng)).normalized();
  const Eigen::Vector3d p1 = PointInFront(rng), p2 = PointInFront(rng), p3 = PointInFront(rng);
  return {Line3{p1 - 0.1 * d1, p1 + 0.1 * d1}, Line3{p2 - 0.1 * d1, p2 + 0.1 * d1}, Line3{p3 - 0.1 * d2, p3 + 0.1 * d2}};
}

inline PrimitiveConfigurationLines Images(const Rigid3d& cam_from_a, const std::array<Line3, 3>& lines) {
  return {ImageLine(cam_from_a, lines[0]), ImageLine(cam_from_a, lines[1]), ImageLine(cam_from_a, lines[2])};
}

// The constraint of a 3-D line for the translation: the point on the line the left ray of its
// middle meets (as a tracker would compute it from the stereo pair of view a), and its images
// in view b.
inline StereoLineConstraint Constraint(const Rigid3d& b_from_a, const Line3& line) {
  const Eigen::Vector3d left_a = ImageLine(Rigid3d(), line), right_a = ImageLine(kRightFromLeft, line);
  const PlueckerLine pl = StereoPairLine(kRightFromLeft, left_a, right_a);
  const Eigen::Vector3d mid = 0.5 * (line.p + line.q);
  // The point of the stereo line nearest to the middle: p0 = d x n / |d|^2 plus its offset.
  const Eigen::Vector3d d = pl.direction.normalized();
  const Eigen::Vector3d p0 = pl.direction.cross(pl.moment) / pl.direction.squaredNorm();
  StereoLineConstraint c;
  c.point_in_a = p0 + d.dot(mid - p0) * d;
  c.left_normal = ImageLine(b_from_a, line);
  c.right_normal = ImageLine(kRightFromLeft * b_from_a, line);
  return c;
}

// The ids (indices) of the first lines of `scene` of which no two are within 20 deg of parallel:
// no candidate configuration among them (the tolerances are 5 deg).
template <typename Line>
std::vector<std::int64_t> LinesWithoutAConfiguration(const std::vector<Line>& scene) {
  std::vector<std::int64_t> ids;
  std::vector<Eigen::Vector3d> directions;
  for (size_t i = 0; i < scene.size(); ++i) {
    const Eigen::Vector3d d = (scene[i].q - scene[i].p).normalized();
    bool distinct = true;
    for (const Eigen::Vector3d& other : directions) distinct = distinct && d.cross(other).norm() > std::sin(20.0 * M_PI / 180.0);
    if (!distinct) continue;
    ids.push_back(static_cast<std::int64_t>(i));
    directions.push_back(d);
  }
  return ids;
}

}  // namespace three_line_test
}  // namespace slt
