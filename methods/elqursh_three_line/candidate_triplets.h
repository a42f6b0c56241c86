// Which lines of a stereo pair may form a primitive configuration of Elqursh & Elgammal (CVPR
// 2011): two parallel lines and a third orthogonal to them (three_line_solver.h).
//
// Elqursh & Elgammal test this in a single image, where any two lines meet at some point and so
// "have" a vanishing point. A stereo pair tells more: the 3-D direction of a line seen in both
// images is the cross product of its two back-projected plane normals, d = l x (E_R^T l')
// (geometry/plucker.h StereoPairLine); in a rectified rig that is the statement that two parallel
// lines have the same vanishing point in the left and the right image. With the unit directions
// d_i of the reference pair's lines, the test is
//   i, j parallel:                |d_i x d_j| <= sin(parallel tolerance),
//   k orthogonal to the pair:     |d_k . d_i| <= sin(orthogonal tolerance) and the same for d_j.
// The candidate triplets (i, j, k), i < j, are listed once per frame so that RANSAC samples only
// plausible configurations: a short list (at most as many triplets as RANSAC may draw) is
// enumerated in a random order, each triplet once; a longer one is sampled uniformly.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

namespace slt {

struct PrimitiveConfigurationTolerances {
  double max_parallel_sine = 0.0;       // sin of the largest angle between parallel lines
  double max_orthogonal_cosine = 0.0;   // cos of the smallest angle between orthogonal lines

  // Unit directions, either sign.
  bool Parallel(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
    return a.cross(b).squaredNorm() <= max_parallel_sine * max_parallel_sine;
  }
  bool Orthogonal(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
    return std::abs(a.dot(b)) <= max_orthogonal_cosine;
  }
};

// (parallel1, parallel2, orthogonal), indices into the directions given to Build.
using LineTriplet = std::array<int, 3>;

class CandidateTriplets {
 public:
  // `unit_directions[i]`: the 3-D direction of line i, unit length, or zero for a line that
  // cannot take part (it is then neither parallel nor orthogonal to anything).
  void Build(const std::vector<Eigen::Vector3d>& unit_directions, const PrimitiveConfigurationTolerances& tolerances);

  std::int64_t size() const { return static_cast<std::int64_t>(orthogonal_.size()); }
  bool empty() const { return orthogonal_.empty(); }
  int parallel_pairs() const { return static_cast<int>(pairs_.size()); }
  // Triplet n, 0 <= n < size().
  LineTriplet At(std::int64_t n) const;
  // Starts the draws of one RANSAC run of at most `max_draws` samples.
  void StartDraws(int max_draws);
  // The next triplet: while size() <= max_draws, each triplet once in a random order, then
  // false; otherwise uniformly among all (false only when there is none).
  bool Next(std::mt19937_64& rng, LineTriplet* triplet);

 private:
  std::vector<std::pair<int, int>> pairs_;  // parallel pairs with at least one orthogonal line
  std::vector<std::int64_t> offsets_;       // pair p's orthogonal lines: [offsets_[p], offsets_[p + 1])
  std::vector<int> orthogonal_;
  // Draws: enumerate_ = walk a random permutation of the triplets (Fisher-Yates, one step per
  // draw), of which drawn_ are done.
  bool enumerate_ = false;
  std::vector<std::int64_t> order_;
  std::int64_t drawn_ = 0;
};

// The roles of three lines that form a candidate configuration, whatever their order: true and
// *roles = (parallel1, parallel2, orthogonal) for the first assignment that passes the test.
bool AssignPrimitiveRoles(const std::array<int, 3>& lines, const std::vector<Eigen::Vector3d>& unit_directions,
                          const PrimitiveConfigurationTolerances& tolerances, LineTriplet* roles);

}  // namespace slt
