// The synthetic stereo line sequences of the benchmark (paper Sec. 5.1 and beyond): a scene of
// 3-D segments, a camera motion, and per frame the segments observed in both images with
// endpoint noise, sliding extents, outliers and a miscalibrated rig as configured.
// docs/simulation.md describes every option, the models and the seeding.
#pragma once

#include <vector>

#include "dataset/stereo_sequence.h"
#include "dataset/trajectory.h"
#include "simulator/scene.h"
#include "simulator/simulation_config.h"

namespace slt {

struct SimulatedSequence {
  // The observations; sequence.rig is the rig given to the tracker (focal_error_px applied).
  StereoSequence sequence;
  // The rig the images were made with.
  StereoRig true_rig;
  // world_from_cam of the left camera per frame; world = the left camera at frame 0, so the
  // first pose is the identity. Times equal the frames' times.
  Trajectory ground_truth;
  // The scene; index = line id (only the first max_features lines when that is set).
  std::vector<Line3d> lines;
  // What the images show (every surface, whatever max_features).
  std::vector<Surface> surfaces;
};

// Throws ConfigError when config.Check() fails. Deterministic: the same config gives
// bit-identical output.
SimulatedSequence Simulate(const SimulationConfig& config);

}  // namespace slt
