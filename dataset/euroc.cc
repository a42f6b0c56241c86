#include "dataset/euroc.h"

#include <charconv>
#include <cmath>
#include <stdexcept>

#include "common/json_reader.h"

namespace slt {
namespace {

// Shortest text that reads back to the same double.
std::string Number(double value) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof(buffer), value).ptr);
}

}  // namespace

std::int64_t EurocTimestampNs(double seconds) { return std::llround(seconds * 1e9); }

void WriteEurocCameraYaml(const std::string& path, const EurocCameraInfo& c) {
  const Eigen::Matrix4d t = c.body_from_cam.ToMatrix4();
  std::string text =
      "%YAML:1.0\n"
      "# General sensor definitions.\n"
      "sensor_type: camera\n"
      "comment: " + c.comment + "\n"
      "\n"
      "# Sensor extrinsics wrt. the body-frame.\n"
      "T_BS:\n"
      "  cols: 4\n"
      "  rows: 4\n"
      "  data: [";
  for (int r = 0; r < 4; ++r) {
    if (r > 0) text += ",\n         ";
    for (int k = 0; k < 4; ++k) text += (k > 0 ? ", " : "") + Number(t(r, k));
  }
  text += "]\n\n# Camera specific definitions.\nrate_hz: " + Number(c.rate_hz) + "\nresolution: [" +
          std::to_string(c.width) + ", " + std::to_string(c.height) + "]\ncamera_model: pinhole\nintrinsics: [" +
          Number(c.intrinsics.fx) + ", " + Number(c.intrinsics.fy) + ", " + Number(c.intrinsics.cx) + ", " +
          Number(c.intrinsics.cy) + "] #fu, fv, cu, cv\ndistortion_model: radial-tangential\ndistortion_coefficients: [" +
          Number(c.distortion[0]) + ", " + Number(c.distortion[1]) + ", " + Number(c.distortion[2]) + ", " +
          Number(c.distortion[3]) + "]\n\n";
  WriteTextFileAtomically(path, text);
}

void WriteEurocImageList(const std::string& path, const std::vector<std::int64_t>& timestamps_ns) {
  std::string text = "#timestamp [ns],filename\n";
  for (const std::int64_t t : timestamps_ns) text += std::to_string(t) + "," + std::to_string(t) + ".png\n";
  WriteTextFileAtomically(path, text);
}

void WriteEurocGroundTruth(const std::string& path, const Trajectory& world_from_body) {
  std::string text =
      "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], "
      "v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], "
      "b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]\n";
  const std::size_t n = world_from_body.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Rigid3d& pose = world_from_body[k].world_from_cam;
    if (!pose.rotation.allFinite() || !pose.translation.allFinite() || !std::isfinite(world_from_body[k].time)) {
      throw std::invalid_argument(path + ": pose " + std::to_string(k) + ": not finite");
    }
    Eigen::Quaterniond q = pose.Quaternion();
    if (q.w() < 0.0) q.coeffs() = -q.coeffs();
    // Central differences inside, one-sided at the ends; zero for a single pose or equal times.
    const std::size_t a = k > 0 ? k - 1 : k, b = k + 1 < n ? k + 1 : k;
    const double dt = world_from_body[b].time - world_from_body[a].time;
    const Eigen::Vector3d velocity =
        dt > 0.0 ? Eigen::Vector3d((world_from_body[b].world_from_cam.translation -
                                    world_from_body[a].world_from_cam.translation) / dt)
                 : Eigen::Vector3d::Zero();
    text += std::to_string(EurocTimestampNs(world_from_body[k].time));
    for (const double v : {pose.translation.x(), pose.translation.y(), pose.translation.z(), q.w(), q.x(), q.y(), q.z(),
                           velocity.x(), velocity.y(), velocity.z()}) {
      text += "," + Number(v);
    }
    text += ",0,0,0,0,0,0\n";
  }
  WriteTextFileAtomically(path, text);
}

}  // namespace slt
