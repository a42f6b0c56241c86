// Camera trajectories and their files.
//
// A trajectory holds, per frame, the pose of the left camera in the world (camera-to-world,
// `world_from_cam`), the world being the left camera at the first frame unless said
// otherwise. Files: TUM (`time tx ty tz qx qy qz qw`) in and out, KITTI (12 numbers of the
// row-major 3x4 world_from_cam, no time) in and out. See docs/formats.md.
#pragma once

#include <string>
#include <vector>

#include "geometry/rigid3.h"

namespace slt {

struct TimedPose {
  double time = 0.0;
  Rigid3d world_from_cam;
};

using Trajectory = std::vector<TimedPose>;

// Throw std::runtime_error naming the file and line on malformed input.
Trajectory ReadTumTrajectory(const std::string& path);
void WriteTumTrajectory(const std::string& path, const Trajectory& trajectory);
// KITTI has no times: frame k gets time k * frame_period.
Trajectory ReadKittiTrajectory(const std::string& path, double frame_period = 0.1);
void WriteKittiTrajectory(const std::string& path, const Trajectory& trajectory);

}  // namespace slt
