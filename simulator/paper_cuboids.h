// Box-like structure for the paper's random-line scene (scene.paper.cuboid_fraction): pieces of
// random cuboids placed among the random segments, so that the scene holds the "primitive
// configurations" (two parallel lines and a third orthogonal to them) that Elqursh & Elgammal's
// method needs (CVPR 2011; methods/elqursh_three_line). The paper's own scene has none: its
// lines are independent, with directions uniform on the sphere. docs/simulation.md describes
// the pieces.
#pragma once

#include <cstdint>
#include <vector>

#include "simulator/simulation_config.h"
#include "simulator/surface.h"

namespace slt {

// round(cuboid_fraction * lines): how many of the paper scene's lines are cuboid edges.
int PaperCuboidLineCount(const PaperSceneConfig& config);

// Appends PaperCuboidLineCount(config) cuboid edges to *lines: alternately a rectangle (the 4
// edges of one face) and a box corner (the 9 edges of the three faces that meet at one corner),
// the last piece cut to the count. Each piece has a uniformly random orientation, edge lengths
// uniform in [min_length_m, max_length_m] and its centre uniform in the box of midpoints. Draws
// from its own stream ("paper_cuboids" of `seed`), so the random segments keep their draws.
void AddPaperCuboids(const PaperSceneConfig& config, std::uint64_t seed, std::vector<Line3d>* lines);

}  // namespace slt
