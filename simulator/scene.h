// The scenes of the simulator: random segments (the paper's protocol) and two structured,
// line-rich interiors (a furnished room, a long corridor), each made of planar textured
// surfaces (simulator/surface.h). docs/simulation.md describes them.
#pragma once

#include <cstdint>
#include <vector>

#include "simulator/simulation_config.h"
#include "simulator/surface.h"

namespace slt {

struct Scene {
  // What the images show. World = the left camera at frame 0 (x right, y down, z forward).
  std::vector<Surface> surfaces;
  // The 3-D line segments; index = line id. In the structured scenes they are the visible
  // edges of the surfaces (LinesFromSurfaces), in the paper scene the random segments, drawn
  // as thin bars (one long edge of each bar is the segment) in front of a textured backdrop.
  std::vector<Line3d> lines;
};

// Draws only from the "scene" stream of `seed`. In the structured scenes the ids are a random
// permutation, so that the first N ids (max_features) are spread over the scene; in the paper
// scene the lines are independent draws, so the first N lines of a scene are the lines of the
// N-line scene with the same seed (with scene.paper.cuboid_fraction > 0 the cuboid edges come
// first, then the random lines, see paper_cuboids.h).
Scene MakeScene(const SceneConfig& config, std::uint64_t seed);

}  // namespace slt
