// Camera motions of the simulator (docs/simulation.md gives the equations).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "dataset/trajectory.h"
#include "simulator/simulation_config.h"

namespace slt {

// world_from_cam of the left camera for frames 0 .. frames-1 at times k / frame_rate. World =
// the left camera at frame 0: the first pose is exactly the identity. Draws only from the
// "motion" stream of `seed`.
// With config.profile set, the profile's motion (docs/simulation.md, "Motion profiles").
Trajectory MakeTrajectory(const MotionConfig& config, int frames, double frame_rate, std::uint64_t seed);

// The road of motion profile "car" as a function of the distance driven s (m): straight along
// +z for straight_m, an arc of turn_radius_m turning by turn_deg (positive: right, towards +x),
// straight on; the camera's centre on it (y = 0), its heading (yaw about the downward y axis,
// positive to the right) and the car's speed there (cruise, braking to the turn speed, the
// turn, accelerating back).
class CarRoute {
 public:
  explicit CarRoute(const CarMotionConfig& config);
  Eigen::Vector3d Position(double s) const;
  double Yaw(double s) const;
  double Speed(double s) const;                     // m/s
  double LongitudinalAcceleration(double s) const;  // m/s^2, negative braking
  double LateralAcceleration(double s) const;       // m/s^2, positive towards the right
  // The distance driven at each time (seconds, increasing), from s = 0 at times.front().
  std::vector<double> Distances(const std::vector<double>& times) const;

 private:
  CarMotionConfig c_;
  double turn_ = 0.0;  // rad
  double arc_end_m_ = 0.0;
};

}  // namespace slt
