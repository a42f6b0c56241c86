#include "dataset/trajectory.h"

#include <Eigen/SVD>
#include <charconv>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include "common/file_io.h"
#include "common/json_reader.h"

namespace slt {
namespace {

// Tolerance on |q| - 1 and on ||R^T R - I||_F: loose enough for files printed with 6 digits,
// tight enough to catch columns in the wrong place or a matrix that is not a rotation.
constexpr double kUnitTolerance = 1e-3;

// Reads a text trajectory line by line, skipping blank and '#' lines, and reports errors as
// "<file>:<line>: <reason>".
class LineParser {
 public:
  explicit LineParser(const std::string& path) : path_(path), in_(OpenInputFile(path)) {}

  // Reads the numbers of the next data line into `values`; false at the end of the file.
  bool Next(std::vector<double>* values) {
    std::string line;
    while (std::getline(in_, line)) {
      ++line_number_;
      values->clear();
      const char* p = line.data();
      const char* const end = p + line.size();
      const auto skip_space = [&] {
        while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
      };
      skip_space();
      if (p == end || *p == '#') continue;
      while (p < end) {
        const char* token_end = p;
        while (token_end < end && *token_end != ' ' && *token_end != '\t' && *token_end != '\r') ++token_end;
        values->push_back(ParseNumber(p, token_end));
        p = token_end;
        skip_space();
      }
      return true;
    }
    if (in_.bad()) throw std::runtime_error(path_ + ": read error");
    return false;
  }

  [[noreturn]] void Fail(const std::string& reason) const {
    throw std::runtime_error(path_ + ":" + std::to_string(line_number_) + ": " + reason);
  }

 private:
  // std::from_chars rather than strtod: it ignores the locale (strtod would stop at the '.'
  // under a locale with decimal commas) and tells where the number ends.
  double ParseNumber(const char* begin, const char* end) const {
    const std::string token(begin, end);
    // from_chars has no leading '+'; other writers may print one.
    if (begin + 1 < end && *begin == '+' && *(begin + 1) != '-') ++begin;
    double value = 0.0;
    const auto [ptr, ec] = std::from_chars(begin, end, value);
    if (ec != std::errc() || ptr != end) Fail("'" + token + "' is not a number");
    if (!std::isfinite(value)) Fail("non-finite value '" + token + "'");
    return value;
  }

  std::string path_;
  std::ifstream in_;
  int line_number_ = 0;
};

// Shortest text that reads back to the same double (C++17 to_chars without a precision).
// Negative zero is written as 0: it reads back to the same pose, and "-0" in a file (an
// identity rotation's quaternion, a camera on an axis) looks like a bug to every reader.
void AppendNumber(double value, std::string* out) {
  if (value == 0.0) value = 0.0;  // -0.0 == 0.0: replaces -0 by +0
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, result.ptr);
}

std::string Describe(double value) {
  std::string text;
  AppendNumber(value, &text);
  return text;
}

[[noreturn]] void FailPose(const std::string& path, size_t index, const TimedPose& pose,
                           const std::string& reason) {
  throw std::invalid_argument(path + ": pose " + std::to_string(index) + " (time " + Describe(pose.time) +
                              "): " + reason);
}

void CheckFinite(const std::string& path, size_t index, const TimedPose& pose) {
  if (!std::isfinite(pose.time) || !pose.world_from_cam.AllFinite()) {
    FailPose(path, index, pose, "not finite");
  }
  if (pose.world_from_cam.translation.cwiseAbs().maxCoeff() > kMaxTrajectoryCoordinate) {
    FailPose(path, index, pose, "translation beyond " + Describe(kMaxTrajectoryCoordinate) + " m");
  }
}

// What the readers accept of a translation (see kMaxTrajectoryCoordinate).
void CheckTranslation(const LineParser& parser, const double* t) {
  for (int i = 0; i < 3; ++i) {
    if (std::abs(t[i]) > kMaxTrajectoryCoordinate) {
      parser.Fail("translation " + Describe(t[i]) + " beyond " + Describe(kMaxTrajectoryCoordinate) + " m");
    }
  }
}

}  // namespace

Trajectory ReadTumTrajectory(const std::string& path) {
  LineParser parser(path);
  Trajectory trajectory;
  std::vector<double> v;
  while (parser.Next(&v)) {
    if (v.size() != 8) {
      parser.Fail("expected 8 numbers (time tx ty tz qx qy qz qw), got " + std::to_string(v.size()));
    }
    if (!trajectory.empty() && v[0] < trajectory.back().time) {
      parser.Fail("time " + Describe(v[0]) + " is before the previous pose's time " +
                  Describe(trajectory.back().time));
    }
    CheckTranslation(parser, &v[1]);
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);  // Eigen's constructor takes w first
    if (std::abs(q.norm() - 1.0) > kUnitTolerance) {
      parser.Fail("quaternion (qx qy qz qw) has norm " + Describe(q.norm()) + ", expected 1");
    }
    trajectory.push_back({v[0], Rigid3d::FromQuaternion(q, Eigen::Vector3d(v[1], v[2], v[3]))});
  }
  return trajectory;
}

TumTrajectoryWriter::TumTrajectoryWriter(const std::string& path) : file_(path) {
  file_.stream() << "# time tx ty tz qx qy qz qw (world_from_cam of the left camera)\n";
}

void TumTrajectoryWriter::Append(const TimedPose& pose) {
  CheckFinite(file_.path(), poses_, pose);
  if (poses_ > 0 && pose.time < previous_time_) FailPose(file_.path(), poses_, pose, "time goes backwards");
  Eigen::Quaterniond q = pose.world_from_cam.Quaternion();
  // q and -q are the same rotation; one sign makes the files comparable line by line.
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const Eigen::Vector3d& t = pose.world_from_cam.translation;
  line_.clear();
  for (double value : {pose.time, t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) {
    AppendNumber(value, &line_);
    line_ += ' ';
  }
  line_.back() = '\n';
  file_.stream() << line_;
  previous_time_ = pose.time;
  ++poses_;
}

void WriteTumTrajectory(const std::string& path, const Trajectory& trajectory) {
  TumTrajectoryWriter writer(path);
  for (const TimedPose& pose : trajectory) writer.Append(pose);
  writer.Close();
}

Trajectory ReadKittiTrajectory(const std::string& path, double frame_period) {
  if (!(frame_period > 0.0) || !std::isfinite(frame_period)) {
    throw std::invalid_argument(path + ": KITTI frame period must be a finite number > 0, got " +
                                Describe(frame_period));
  }
  LineParser parser(path);
  Trajectory trajectory;
  std::vector<double> v;
  while (parser.Next(&v)) {
    if (v.size() != 12) {
      parser.Fail("expected 12 numbers (row-major 3x4 world_from_cam), got " + std::to_string(v.size()));
    }
    const Eigen::Map<const Eigen::Matrix<double, 3, 4, Eigen::RowMajor>> m(v.data());
    const double translation[3] = {v[3], v[7], v[11]};
    CheckTranslation(parser, translation);
    const Eigen::Matrix3d r = m.leftCols<3>();
    const double orthogonality_error = (r.transpose() * r - Eigen::Matrix3d::Identity()).norm();
    if (orthogonality_error > kUnitTolerance || r.determinant() < 0.0) {
      parser.Fail("the left 3x3 block is not a rotation matrix (||R^T R - I|| = " +
                  Describe(orthogonality_error) + ", det = " + Describe(r.determinant()) + ")");
    }
    // Printed rotations are orthonormal only to the printed digits; the rest of the code
    // assumes an exact rotation, so take the nearest one (U V^T of the SVD).
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Matrix3d rotation = svd.matrixU() * svd.matrixV().transpose();
    trajectory.push_back({static_cast<double>(trajectory.size()) * frame_period, Rigid3d(rotation, m.col(3))});
  }
  return trajectory;
}

void WriteKittiTrajectory(const std::string& path, const Trajectory& trajectory) {
  std::string out;
  for (size_t k = 0; k < trajectory.size(); ++k) {
    CheckFinite(path, k, trajectory[k]);
    const Matrix34d m = trajectory[k].world_from_cam.ToMatrix3x4();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 4; ++j) {
        AppendNumber(m(i, j), &out);
        out += ' ';
      }
    }
    out.back() = '\n';
  }
  WriteTextFileAtomically(path, out);
}

double PathLengthM(const Trajectory& trajectory) {
  double length = 0.0;
  for (size_t k = 1; k < trajectory.size(); ++k) {
    length += (trajectory[k].world_from_cam.translation - trajectory[k - 1].world_from_cam.translation).norm();
  }
  return length;
}

}  // namespace slt
