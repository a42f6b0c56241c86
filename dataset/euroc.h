// The text files of EuRoC's ASL dataset layout (Burri et al., "The EuRoC micro aerial vehicle
// datasets", IJRR 2016), written in the dataset's own style so that tools made for EuRoC read
// our sequences (docs/formats.md, "EuRoC / ASL layout"):
//
//   mav0/cam0/sensor.yaml, mav0/cam0/data.csv (and cam1)   camera calibration, image list
//   mav0/state_groundtruth_estimate0/data.csv              poses of the body frame
//
// The images themselves (mav0/camN/data/<timestamp>.png) are written by render/.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dataset/trajectory.h"
#include "geometry/camera.h"

namespace slt {

// One camera's sensor.yaml.
struct EurocCameraInfo {
  std::string comment;
  Rigid3d body_from_cam;  // EuRoC's T_BS: the camera's pose in the body frame
  double rate_hz = 20.0;
  int width = 752;
  int height = 480;
  PinholeCamera intrinsics;                 // [fu, fv, cu, cv]
  std::array<double, 4> distortion{};       // radial-tangential [k1, k2, p1, p2]
};

// EuRoC's timestamps: integer nanoseconds.
std::int64_t EurocTimestampNs(double seconds);

// Atomic writes; std::runtime_error naming the file on failure.
void WriteEurocCameraYaml(const std::string& path, const EurocCameraInfo& camera);
// "#timestamp [ns],filename" and one "<t>,<t>.png" line per image.
void WriteEurocImageList(const std::string& path, const std::vector<std::int64_t>& timestamps_ns);
// Readers of the same files (ours and EuRoC's own): std::runtime_error naming the file and the
// key or line on anything missing or malformed. The camera reader takes the subset of YAML these
// files use ("key: value", "key: [a, b, ...]" possibly over several lines, T_BS's "data").
EurocCameraInfo ReadEurocCameraYaml(const std::string& path);
// One entry per image line: the timestamp and the file name as written (relative to data/).
struct EurocImageEntry {
  std::int64_t timestamp_ns = 0;
  std::string filename;
};
std::vector<EurocImageEntry> ReadEurocImageList(const std::string& path);

// state_groundtruth_estimate0/data.csv: per pose the position p_RS_R, the quaternion q_RS
// (w, x, y, z) of world_from_body, the velocity v_RS_R (central differences of the positions)
// and zero gyroscope and accelerometer biases.
void WriteEurocGroundTruth(const std::string& path, const Trajectory& world_from_body);
// Reads the same file (ours or EuRoC's own, at least the 8 columns timestamp, p_RS_R, q_RS):
// world_from_body, times in seconds. std::runtime_error naming the file and line on a short or
// malformed line, a quaternion that is not of unit norm (1e-3), or times that do not increase.
Trajectory ReadEurocGroundTruth(const std::string& path);

}  // namespace slt
