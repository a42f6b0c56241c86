#include "dataset/euroc.h"

#include <Eigen/SVD>
#include <charconv>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
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
    if (!pose.AllFinite() || !std::isfinite(world_from_body[k].time)) {
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

namespace slt {
namespace {

[[noreturn]] void FailAt(const std::string& path, const std::string& what) {
  throw std::runtime_error(path + ": " + what);
}

std::string Trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

// "[1, 2.5, 3]" -> numbers; throws naming the key.
std::vector<double> ParseNumberList(const std::string& text, const std::string& path, const std::string& key) {
  const size_t open = text.find('['), close = text.rfind(']');
  if (open == std::string::npos || close == std::string::npos || close < open) {
    FailAt(path, "key '" + key + "': expected a list [a, b, ...], got '" + text + "'");
  }
  std::vector<double> values;
  std::stringstream items(text.substr(open + 1, close - open - 1));
  std::string item;
  while (std::getline(items, item, ',')) {
    item = Trim(item);
    if (item.empty()) continue;
    double v = 0.0;
    const auto [end, error] = std::from_chars(item.data(), item.data() + item.size(), v);
    if (error != std::errc() || end != item.data() + item.size() || !std::isfinite(v)) {
      FailAt(path, "key '" + key + "': not a finite number: '" + item + "'");
    }
    values.push_back(v);
  }
  return values;
}

}  // namespace

EurocCameraInfo ReadEurocCameraYaml(const std::string& path) {
  std::ifstream in(path);
  if (!in) FailAt(path, "cannot read the camera calibration (sensor.yaml)");
  // Flattened "key" -> "value" with nested keys joined by '.', lists joined over lines.
  std::map<std::string, std::string> values;
  std::string line, parent, pending_key, pending_value;
  while (std::getline(in, line)) {
    const size_t hash = line.find('#');
    if (hash != std::string::npos && line.rfind("%YAML", 0) != 0) line = line.substr(0, hash);
    if (line.rfind("%YAML", 0) == 0 || Trim(line).empty()) continue;
    if (!pending_key.empty()) {
      pending_value += " " + Trim(line);
      if (pending_value.find(']') != std::string::npos) {
        values[pending_key] = pending_value;
        pending_key.clear();
      }
      continue;
    }
    const size_t colon = line.find(':');
    if (colon == std::string::npos) FailAt(path, "expected 'key: value', got '" + Trim(line) + "'");
    const bool indented = !line.empty() && (line[0] == ' ' || line[0] == '\t');
    const std::string key = Trim(line.substr(0, colon));
    const std::string value = Trim(line.substr(colon + 1));
    if (!indented) parent = value.empty() ? key : "";
    const std::string full = indented && !parent.empty() ? parent + "." + key : key;
    if (value.find('[') != std::string::npos && value.find(']') == std::string::npos) {
      pending_key = full;
      pending_value = value;
    } else {
      values[full] = value;
    }
  }
  if (!pending_key.empty()) FailAt(path, "key '" + pending_key + "': list not closed with ']'");
  auto require = [&](const std::string& key) -> const std::string& {
    const auto it = values.find(key);
    if (it == values.end()) FailAt(path, "missing key '" + key + "'");
    return it->second;
  };
  auto list = [&](const std::string& key, size_t size) {
    const std::vector<double> v = ParseNumberList(require(key), path, key);
    if (v.size() != size) {
      FailAt(path, "key '" + key + "': expected " + std::to_string(size) + " numbers, got " + std::to_string(v.size()));
    }
    return v;
  };
  EurocCameraInfo camera;
  if (values.count("comment")) camera.comment = values["comment"];
  if (values.count("camera_model") && values["camera_model"] != "pinhole") {
    FailAt(path, "key 'camera_model': only \"pinhole\" is supported, got '" + values["camera_model"] + "'");
  }
  const std::vector<double> t = list("T_BS.data", 16);
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = t[4 * r + c];
  }
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-4 || r.determinant() < 0.0 ||
      (m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9) {
    FailAt(path, "key 'T_BS.data': not a rigid transform (rotation not orthonormal or last row not [0 0 0 1])");
  }
  // Re-orthonormalise the printed rotation (EuRoC prints about 12 digits).
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  camera.body_from_cam = Rigid3d(svd.matrixU() * svd.matrixV().transpose(), m.topRightCorner<3, 1>());
  if (values.count("rate_hz")) camera.rate_hz = ParseNumberList("[" + values["rate_hz"] + "]", path, "rate_hz").at(0);
  const std::vector<double> resolution = list("resolution", 2);
  if (resolution[0] < 1 || resolution[1] < 1 || resolution[0] != std::floor(resolution[0]) ||
      resolution[1] != std::floor(resolution[1])) {
    FailAt(path, "key 'resolution': expected two positive integers");
  }
  camera.width = static_cast<int>(resolution[0]);
  camera.height = static_cast<int>(resolution[1]);
  const std::vector<double> k = list("intrinsics", 4);
  camera.intrinsics = PinholeCamera{k[0], k[1], k[2], k[3]};
  try {
    camera.intrinsics.Check("intrinsics");
  } catch (const std::exception& e) {
    FailAt(path, std::string("key 'intrinsics': ") + e.what());
  }
  if (values.count("distortion_model") && values["distortion_model"] != "radial-tangential") {
    FailAt(path, "key 'distortion_model': only \"radial-tangential\" is supported, got '" +
                     values["distortion_model"] + "'");
  }
  if (values.count("distortion_coefficients")) {
    const std::vector<double> d = list("distortion_coefficients", 4);
    for (int i = 0; i < 4; ++i) camera.distortion[i] = d[i];
  }
  return camera;
}

namespace {

// Calls `parse(line, where)` for every line that is neither blank nor a '#' comment, trimmed,
// with where = "line N" for messages.
void ForEachDataLine(const std::string& path, const std::string& what,
                     const std::function<void(const std::string&, const std::string&)>& parse) {
  std::ifstream in(path);
  if (!in) FailAt(path, "cannot read the " + what);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    line = Trim(line);
    if (line.empty() || line[0] == '#') continue;
    parse(line, "line " + std::to_string(number));
  }
}

std::int64_t ParseTimestampNs(const std::string& text, const std::string& path, const std::string& where) {
  std::int64_t stamp = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), stamp);
  if (error != std::errc() || end != text.data() + text.size()) {
    FailAt(path, where + ": timestamp is not an integer: '" + text + "'");
  }
  return stamp;
}

}  // namespace

std::vector<EurocImageEntry> ReadEurocImageList(const std::string& path) {
  std::vector<EurocImageEntry> entries;
  ForEachDataLine(path, "image list", [&](const std::string& line, const std::string& where) {
    const size_t comma = line.find(',');
    if (comma == std::string::npos) FailAt(path, where + ": expected 'timestamp,filename', got '" + line + "'");
    EurocImageEntry entry;
    entry.timestamp_ns = ParseTimestampNs(Trim(line.substr(0, comma)), path, where);
    entry.filename = Trim(line.substr(comma + 1));
    if (entry.filename.empty()) FailAt(path, where + ": empty file name");
    if (!entries.empty() && entry.timestamp_ns <= entries.back().timestamp_ns) {
      FailAt(path, where + ": timestamps must increase");
    }
    entries.push_back(std::move(entry));
  });
  return entries;
}

Trajectory ReadEurocGroundTruth(const std::string& path) {
  Trajectory trajectory;
  ForEachDataLine(path, "ground truth", [&](const std::string& line, const std::string& where_line) {
    const std::string where = where_line + ": ";
    std::stringstream fields(line);
    std::string field;
    std::getline(fields, field, ',');
    const std::int64_t stamp = ParseTimestampNs(Trim(field), path, where_line);
    double v[7];
    for (int i = 0; i < 7; ++i) {
      if (!std::getline(fields, field, ',')) {
        FailAt(path, where + "expected timestamp, p_RS_R (3) and q_RS (w x y z), got " + std::to_string(i + 1) +
                         " columns");
      }
      field = Trim(field);
      const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), v[i]);
      if (error != std::errc() || end != field.data() + field.size() || !std::isfinite(v[i])) {
        FailAt(path, where + "column " + std::to_string(i + 2) + ": not a finite number: '" + field + "'");
      }
    }
    const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 1e-3) FailAt(path, where + "quaternion q_RS does not have unit norm");
    const double time = static_cast<double>(stamp) * 1e-9;
    if (!trajectory.empty() && !(time > trajectory.back().time)) FailAt(path, where + "timestamps must increase");
    trajectory.push_back({time, Rigid3d::FromQuaternion(q.normalized(), Eigen::Vector3d(v[0], v[1], v[2]))});
  });
  return trajectory;
}

}  // namespace slt
