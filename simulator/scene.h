// The 3-D scenes of the simulator: random segments (the paper's protocol) and two structured,
// line-rich interiors (a furnished room, a long corridor). docs/simulation.md describes them.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "simulator/simulation_config.h"

namespace slt {

// A 3-D line segment, endpoints in world coordinates.
struct Line3d {
  Eigen::Vector3d p;
  Eigen::Vector3d q;
};

// The scene's segments; index = line id. World = the left camera at frame 0 (x right, y down,
// z forward). Draws only from the "scene" stream of `seed`. In the structured scenes the ids
// are a random permutation, so that the first N ids (max_features) are spread over the scene;
// in the paper scene the lines are independent draws, so the first N lines of a scene are the
// lines of the N-line scene with the same seed (with scene.paper.cuboid_fraction > 0 the cuboid
// edges come first, then the random lines, see paper_cuboids.h).
std::vector<Line3d> MakeScene(const SceneConfig& config, std::uint64_t seed);

}  // namespace slt
