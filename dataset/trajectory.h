// Camera trajectories and their files.
//
// A trajectory holds, per frame, the pose of the left camera in the world (camera-to-world,
// `world_from_cam`), the world being the left camera at the first frame unless said
// otherwise. Files: TUM (`time tx ty tz qx qy qz qw`) in and out, KITTI (12 numbers of the
// row-major 3x4 world_from_cam, no time) in and out. Times in seconds, translations in metres.
// See docs/formats.md.
//
// Readers skip blank lines and lines starting with '#', accept any whitespace between numbers,
// and require finite numbers, translations within kMaxTrajectoryCoordinate and non-decreasing
// times. TUM quaternions are normalised (a norm
// further than 1e-3 from 1 is an error: the file is not what it claims to be); KITTI rotation
// blocks are projected onto the nearest rotation (an orthogonality error above 1e-3 or a
// reflection is an error). Writers print every number in the shortest form that reads back
// to the same double, so a written trajectory reads back exactly (up to the quaternion ->
// matrix conversion, ~1e-16).
#pragma once

#include <string>
#include <vector>

#include "common/file_io.h"
#include "geometry/rigid3.h"

namespace slt {

// Largest |x|, |y| or |z| of a translation the readers and writers accept, in metres (ten times
// Saturn's distance from the Sun): no camera trajectory goes further, and beyond ~1e154 m the
// squared errors of the metrics overflow to infinity.
constexpr double kMaxTrajectoryCoordinate = 1e13;

struct TimedPose {
  double time = 0.0;  // seconds
  Rigid3d world_from_cam;
};

using Trajectory = std::vector<TimedPose>;

// The length of the camera centres' polyline, metres (0 for fewer than two poses).
double PathLengthM(const Trajectory& trajectory);

// Throw std::runtime_error "<file>:<line>: <what is wrong>" on malformed input.
Trajectory ReadTumTrajectory(const std::string& path);
// Writes atomically with a '#' header line. Throws std::invalid_argument naming the pose when a
// value is not finite, a translation is beyond kMaxTrajectoryCoordinate or times decrease (the
// reader would reject the file).
void WriteTumTrajectory(const std::string& path, const Trajectory& trajectory);
// The same file written pose by pose (memory flat over any length), put in place by Close(); a
// writer destroyed before Close() leaves no file. Append throws as WriteTumTrajectory does.
class TumTrajectoryWriter {
 public:
  explicit TumTrajectoryWriter(const std::string& path);
  void Append(const TimedPose& pose);
  void Close() { file_.Commit(); }

 private:
  AtomicFileWriter file_;
  std::string line_;
  size_t poses_ = 0;
  double previous_time_ = 0.0;
};
// KITTI has no times: frame k gets time k * frame_period (seconds; std::invalid_argument unless
// finite and > 0).
Trajectory ReadKittiTrajectory(const std::string& path, double frame_period = 0.1);
// Times are dropped. Throws std::invalid_argument naming the pose when a value is not finite or
// a translation is beyond kMaxTrajectoryCoordinate.
void WriteKittiTrajectory(const std::string& path, const Trajectory& trajectory);

}  // namespace slt
