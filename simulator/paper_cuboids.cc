#include "simulator/paper_cuboids.h"

#include <Eigen/Geometry>
#include <cmath>

#include "simulator/random_draws.h"

namespace slt {

int PaperCuboidLineCount(const PaperSceneConfig& config) {
  return static_cast<int>(std::lround(config.cuboid_fraction * config.lines));
}

void AddPaperCuboids(const PaperSceneConfig& c, std::uint64_t seed, std::vector<Line3d>* lines) {
  RandomStream rng = MakeStream(seed, "paper_cuboids");
  const int count = PaperCuboidLineCount(c);
  int added = 0;
  auto add = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
    if (added < count) lines->push_back({p, q});
    ++added;
  };
  for (int piece = 0; added < count; ++piece) {
    Eigen::Vector3d center;
    for (int k = 0; k < 3; ++k) center[k] = c.box_center_m[k] + c.box_size_m[k] * Uniform(rng, -0.5, 0.5);
    // A uniformly random orientation: e1 uniform on the sphere, e2 uniform on the circle
    // orthogonal to it (a second unit vector, projected; redrawn in the rare near-parallel case).
    const Eigen::Vector3d e1 = UniformUnitVector(rng);
    Eigen::Vector3d e2;
    do {
      const Eigen::Vector3d u = UniformUnitVector(rng);
      e2 = u - u.dot(e1) * e1;
    } while (e2.norm() < 1e-3);
    e2.normalize();
    const Eigen::Vector3d e3 = e1.cross(e2);
    // Half edge lengths along e1, e2, e3.
    const Eigen::Vector3d a = e1 * 0.5 * Uniform(rng, c.min_length_m, c.max_length_m);
    const Eigen::Vector3d b = e2 * 0.5 * Uniform(rng, c.min_length_m, c.max_length_m);
    const Eigen::Vector3d h = e3 * 0.5 * Uniform(rng, c.min_length_m, c.max_length_m);
    if (piece % 2 == 0) {
      // A rectangle: the face through the centre spanned by e1 and e2.
      add(center - a - b, center + a - b);
      add(center + a - b, center + a + b);
      add(center + a + b, center - a + b);
      add(center - a + b, center - a - b);
    } else {
      // A box corner: from the corner v = center + a + b + h, its three edges and the two far
      // edges of each of the three faces that meet there.
      const Eigen::Vector3d v = center + a + b + h;
      const Eigen::Vector3d along[3] = {2.0 * a, 2.0 * b, 2.0 * h};
      for (int i = 0; i < 3; ++i) add(v, v - along[i]);
      for (int i = 0; i < 3; ++i) {
        const Eigen::Vector3d& u = along[i];
        const Eigen::Vector3d& w = along[(i + 1) % 3];
        add(v - u, v - u - w);
        add(v - w, v - u - w);
      }
    }
  }
}

}  // namespace slt
