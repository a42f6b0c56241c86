#include "dataset/kitti.h"

#include <cstdio>
#include <stdexcept>

#include "common/file_io.h"

namespace slt {
namespace {

// KITTI's own number format ("7.188560000000e+02"): %.12e.
std::string KittiNumber(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.12e", value);
  return buffer;
}

std::string ProjectionLine(const char* key, const PinholeCamera& k, double tx) {
  const double p[12] = {k.fx, 0.0, k.cx, k.fx * tx, 0.0, k.fy, k.cy, 0.0, 0.0, 0.0, 1.0, 0.0};
  std::string line = key;
  line += ":";
  for (const double value : p) line += " " + KittiNumber(value);
  return line + "\n";
}

}  // namespace

void WriteKittiCalibration(const std::string& path, const StereoRig& rig) {
  const PinholeCamera &l = rig.left, &r = rig.right;
  const Eigen::Vector3d& t = rig.right_from_left.translation;
  if (l.fx != r.fx || l.fy != r.fy || l.cx != r.cx || l.cy != r.cy ||
      !rig.right_from_left.rotation.isIdentity(0.0) || t.y() != 0.0 || t.z() != 0.0 || !(t.x() < 0.0)) {
    throw std::invalid_argument(path +
                                ": KITTI's calib.txt holds a rectified pair only (equal intrinsics, the right camera "
                                "along +x of the left, no rotation); this rig is not one");
  }
  WriteTextFileAtomically(path, ProjectionLine("P0", l, 0.0) + ProjectionLine("P1", r, t.x()));
}

void WriteKittiTimes(const std::string& path, const std::vector<double>& times_s) {
  std::string text;
  for (const double t : times_s) text += KittiNumber(t) + "\n";
  WriteTextFileAtomically(path, text);
}

std::string KittiImageName(int frame) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%06d.png", frame);
  return buffer;
}

}  // namespace slt
