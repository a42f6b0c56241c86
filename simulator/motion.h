// Camera motions of the simulator (docs/simulation.md gives the equations).
#pragma once

#include <cstdint>

#include "dataset/trajectory.h"
#include "simulator/simulation_config.h"

namespace slt {

// world_from_cam of the left camera for frames 0 .. frames-1 at times k / frame_rate. World =
// the left camera at frame 0: the first pose is exactly the identity. Draws only from the
// "motion" stream of `seed`.
Trajectory MakeTrajectory(const MotionConfig& config, int frames, double frame_rate, std::uint64_t seed);

}  // namespace slt
