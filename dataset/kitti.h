// The text files of KITTI odometry's layout (Geiger, Lenz and Urtasun, "Are we ready for
// autonomous driving? The KITTI vision benchmark suite", CVPR 2012), written in the dataset's
// own style so that tools made for KITTI read our sequences (docs/formats.md, "KITTI odometry
// layout"):
//
//   calib.txt   "P0: 12 numbers" and "P1: ...", the 3 x 4 projection matrices of the rectified
//               grey pair, row-major: P0 = K [I | 0], P1 = K [I | t] with t = (-baseline, 0, 0)
//   times.txt   one time in seconds per frame
//   poses.txt   the left camera's poses (dataset/trajectory.h, WriteKittiTrajectory)
//
// The images themselves (image_0/<000000>.png, image_1/...) are written by render/; the reader
// of the whole layout is frontend/image_sequence.h.
#pragma once

#include <string>
#include <vector>

#include "geometry/camera.h"

namespace slt {

// Throws std::invalid_argument when the rig is not a rectified pair (the same intrinsics in
// both cameras, the right camera displaced along +x only, no rotation), which is all KITTI's
// calib.txt can state; std::runtime_error naming the file when it cannot be written.
void WriteKittiCalibration(const std::string& path, const StereoRig& rig);
// Atomic write; std::runtime_error naming the file.
void WriteKittiTimes(const std::string& path, const std::vector<double>& times_s);
// The image name of frame k: "000000.png" (six digits, more when k needs them).
std::string KittiImageName(int frame);

}  // namespace slt
