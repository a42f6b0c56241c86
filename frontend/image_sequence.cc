#include "frontend/image_sequence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "dataset/euroc.h"
#include "frontend/stereo_rectification.h"

namespace slt {
namespace fs = std::filesystem;
namespace {

cv::Mat ReadGrey(const std::string& path, int width, int height) {
  if (!fs::exists(path)) throw std::runtime_error(path + ": image missing");
  cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (image.empty()) throw std::runtime_error(path + ": cannot read the image (not a PNG OpenCV can decode?)");
  if (image.depth() != CV_8U) throw std::runtime_error(path + ": expected 8-bit pixels");
  if (image.channels() == 3) cv::cvtColor(image, image, cv::COLOR_BGR2GRAY);
  else if (image.channels() == 4) cv::cvtColor(image, image, cv::COLOR_BGRA2GRAY);
  else if (image.channels() != 1) throw std::runtime_error(path + ": unexpected number of channels");
  if (image.cols != width || image.rows != height) {
    throw std::runtime_error(path + ": image is " + std::to_string(image.cols) + " x " + std::to_string(image.rows) +
                             ", the calibration says " + std::to_string(width) + " x " + std::to_string(height));
  }
  return image;
}

// world_from_left = world_from_body * body_from_left, then to the rectified left camera.
Trajectory LeftCameraTrajectory(const Trajectory& world_from_body, const Rigid3d& body_from_left,
                                const Eigen::Matrix3d& rectified_from_left) {
  const Rigid3d body_from_rectified = body_from_left * Rigid3d(rectified_from_left.transpose(), Eigen::Vector3d::Zero());
  Trajectory out;
  out.reserve(world_from_body.size());
  for (const TimedPose& pose : world_from_body) out.push_back({pose.time, pose.world_from_cam * body_from_rectified});
  return out;
}

class AslSource : public StereoImageSource {
 public:
  AslSource(const std::string& path, const std::string& ground_truth) {
    const fs::path root(path);
    const fs::path mav0 = fs::exists(root / "mav0") ? root / "mav0" : root;
    cam_[0] = mav0 / "cam0";
    cam_[1] = mav0 / "cam1";
    EurocCameraInfo info[2];
    std::vector<EurocImageEntry> lists[2];
    for (int c = 0; c < 2; ++c) {
      info[c] = ReadEurocCameraYaml((cam_[c] / "sensor.yaml").string());
      lists[c] = ReadEurocImageList((cam_[c] / "data.csv").string());
    }
    const std::string yaml1 = (cam_[1] / "sensor.yaml").string();
    if (info[0].width != info[1].width || info[0].height != info[1].height) {
      throw std::runtime_error(yaml1 + ": key 'resolution': differs from cam0's");
    }
    // Pairs by equal timestamps (both lists increase: ReadEurocImageList checks).
    size_t j = 0;
    for (const EurocImageEntry& left : lists[0]) {
      while (j < lists[1].size() && lists[1][j].timestamp_ns < left.timestamp_ns) ++j;
      if (j < lists[1].size() && lists[1][j].timestamp_ns == left.timestamp_ns) pairs_.push_back({left, lists[1][j]});
    }
    unpaired_ = static_cast<int>(lists[0].size() + lists[1].size() - 2 * pairs_.size());
    if (pairs_.empty()) {
      throw std::runtime_error((cam_[1] / "data.csv").string() + ": no timestamp in common with " +
                               (cam_[0] / "data.csv").string() + " (" + std::to_string(lists[0].size()) + " and " +
                               std::to_string(lists[1].size()) + " images listed)");
    }
    for (const auto& pair : pairs_) {
      for (int c = 0; c < 2; ++c) {
        const fs::path file = cam_[c] / "data" / (c == 0 ? pair.first : pair.second).filename;
        if (!fs::exists(file)) {
          throw std::runtime_error(file.string() + ": image missing (listed in " + (cam_[c] / "data.csv").string() + ")");
        }
      }
    }
    DistortedStereoCalibration calibration;
    calibration.width = info[0].width;
    calibration.height = info[0].height;
    calibration.left = info[0].intrinsics;
    calibration.right = info[1].intrinsics;
    calibration.left_distortion = info[0].distortion;
    calibration.right_distortion = info[1].distortion;
    // right_from_left = cam1_from_body * body_from_cam0.
    calibration.right_from_left = info[1].body_from_cam.Inverse() * info[0].body_from_cam;
    try {
      rectifier_.emplace(calibration);
    } catch (const std::exception& e) {
      throw std::runtime_error(yaml1 + ": unusable stereo rig: " + e.what());
    }
    try {
      rectifier_->rig().Check();
    } catch (const std::exception& e) {
      throw std::runtime_error(yaml1 + ": unusable stereo rig: " + e.what());
    }
    description_ = "ASL layout at " + mav0.string();

    std::vector<fs::path> candidates;
    if (!ground_truth.empty()) {
      candidates = {ground_truth};
      if (!fs::exists(ground_truth)) throw std::runtime_error(ground_truth + ": ground truth file missing");
    } else {
      candidates = {mav0 / "state_groundtruth_estimate0" / "data.csv", root / "groundtruth_body.tum",
                    mav0 / "groundtruth_body.tum"};
    }
    for (const fs::path& file : candidates) {
      if (!fs::exists(file)) continue;
      const Trajectory world_from_body =
          file.extension() == ".csv" ? ReadEurocGroundTruth(file.string()) : ReadTumTrajectory(file.string());
      ground_truth_ = LeftCameraTrajectory(world_from_body, info[0].body_from_cam, rectifier_->rectified_from_left());
      ground_truth_file_ = file.string();
      break;
    }
  }
  const StereoRig& rig() const override { return rectifier_->rig(); }
  int size() const override { return static_cast<int>(pairs_.size()); }
  double Time(int index) const override { return pairs_.at(index).first.timestamp_ns * 1e-9; }
  StereoImages Read(int index) const override {
    StereoImages out;
    out.time = Time(index);
    const StereoRig& r = rig();
    out.left = rectifier_->Rectify(ReadGrey((cam_[0] / "data" / pairs_[index].first.filename).string(), r.width, r.height), 0);
    out.right =
        rectifier_->Rectify(ReadGrey((cam_[1] / "data" / pairs_[index].second.filename).string(), r.width, r.height), 1);
    return out;
  }
  std::string Describe() const override {
    std::string text = description_ + ": " + std::to_string(size()) + " stereo pairs, " + std::to_string(rig().width) +
                       " x " + std::to_string(rig().height);
    if (rectifier_->active()) text += ", undistorted and rectified";
    if (unpaired_ > 0) text += "; " + std::to_string(unpaired_) + " images without a partner skipped";
    return text;
  }

 private:
  fs::path cam_[2];
  std::vector<std::pair<EurocImageEntry, EurocImageEntry>> pairs_;
  int unpaired_ = 0;
  std::optional<StereoRectifier> rectifier_;
  std::string description_;
};

// The 3 x 4 projection matrix `key` ("P0", "P1") of a KITTI calib.txt: the line "P0: 12 numbers"
// (row-major), or, in files without keys, the first (P0) or second (P1) line of 12 numbers.
Eigen::Matrix<double, 3, 4> ReadProjection(const std::string& calib, const std::string& key) {
  std::ifstream in(calib);
  if (!in) throw std::runtime_error(calib + ": cannot read the calibration");
  std::vector<std::vector<double>> unkeyed;
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    std::string name;
    if (!(fields >> name)) continue;
    if (name == key + ":") {
      Eigen::Matrix<double, 3, 4> p;
      for (int i = 0; i < 12; ++i) {
        if (!(fields >> p(i / 4, i % 4)) || !std::isfinite(p(i / 4, i % 4))) {
          throw std::runtime_error(calib + ": key '" + key + "': expected 12 numbers");
        }
      }
      return p;
    }
    std::istringstream numbers(line);
    std::vector<double> values;
    for (double v; numbers >> v;) values.push_back(v);
    if (numbers.eof() && values.size() == 12) unkeyed.push_back(values);
  }
  const size_t index = key == "P0" ? 0 : 1;
  if (unkeyed.size() >= 2) {
    Eigen::Matrix<double, 3, 4> p;
    for (int i = 0; i < 12; ++i) p(i / 4, i % 4) = unkeyed[index][i];
    return p;
  }
  throw std::runtime_error(calib + ": missing key '" + key + ":' (nor two lines of 12 numbers, P0 and P1)");
}

// The number of "<000000>.png" files of a KITTI image folder, numbered from 0 without gaps.
int CountKittiImages(const fs::path& folder) {
  if (!fs::is_directory(folder)) throw std::runtime_error(folder.string() + ": image folder missing");
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() == ".png") names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  char expected[32];
  for (size_t k = 0; k < names.size(); ++k) {
    std::snprintf(expected, sizeof(expected), "%06zu.png", k);
    if (names[k] != expected) {
      throw std::runtime_error((folder / expected).string() + ": image missing (the folder has " +
                               std::to_string(names.size()) + " PNGs, numbered from 000000.png without gaps in KITTI)");
    }
  }
  if (names.empty()) throw std::runtime_error((folder / "000000.png").string() + ": image missing (no PNG in the folder)");
  return static_cast<int>(names.size());
}

// KITTI odometry: the images are rectified, P_i = K_i [I | t_i], so right_from_left =
// (I, t_1 - t_0) with t_i = K_i^-1 P_i(:, 3).
class KittiSource : public StereoImageSource {
 public:
  KittiSource(const std::string& path, const std::string& ground_truth) : dir_(path) {
    const bool named_lr = !fs::exists(dir_ / "image_0") && fs::exists(dir_ / "image_l");
    folder_[0] = dir_ / (named_lr ? "image_l" : "image_0");
    folder_[1] = dir_ / (named_lr ? "image_r" : "image_1");
    const std::string calib = (dir_ / "calib.txt").string();
    if (!fs::exists(calib)) throw std::runtime_error(calib + ": calibration missing");
    PinholeCamera k[2];
    Eigen::Vector3d t[2];
    for (int c = 0; c < 2; ++c) {
      const std::string key = "P" + std::to_string(c);
      const Eigen::Matrix<double, 3, 4> p = ReadProjection(calib, key);
      k[c] = PinholeCamera{p(0, 0), p(1, 1), p(0, 2), p(1, 2)};
      if (std::abs(p(0, 1)) > 1e-9 || std::abs(p(1, 0)) > 1e-9 || std::abs(p(2, 0)) > 1e-9 ||
          std::abs(p(2, 1)) > 1e-9 || std::abs(p(2, 2) - 1.0) > 1e-9 || !(p(0, 0) > 0.0) || !(p(1, 1) > 0.0)) {
        throw std::runtime_error(calib + ": key '" + key + "': not a rectified K [I | t]");
      }
      t[c] = k[c].K().inverse() * p.col(3);
    }
    for (int c = 0; c < 2; ++c) counts_[c] = CountKittiImages(folder_[c]);
    if (counts_[0] != counts_[1]) {
      throw std::runtime_error(folder_[1].string() + ": " + std::to_string(counts_[1]) + " images, but " +
                               folder_[0].string() + " has " + std::to_string(counts_[0]));
    }
    const fs::path times = dir_ / "times.txt";
    if (fs::exists(times)) {
      std::ifstream in(times);
      if (!in) throw std::runtime_error(times.string() + ": cannot read the frame times");
      std::string token;
      while (in >> token) {
        double value = 0.0;
        try {
          size_t used = 0;
          value = std::stod(token, &used);
          if (used != token.size() || !std::isfinite(value)) throw std::invalid_argument(token);
        } catch (const std::exception&) {
          throw std::runtime_error(times.string() + ": line " + std::to_string(times_.size() + 1) +
                                   ": not a number: '" + token + "'");
        }
        if (!times_.empty() && !(value > times_.back())) {
          throw std::runtime_error(times.string() + ": line " + std::to_string(times_.size() + 1) +
                                   ": times must increase");
        }
        times_.push_back(value);
      }
      if (static_cast<int>(times_.size()) != counts_[0]) {
        throw std::runtime_error(times.string() + ": " + std::to_string(times_.size()) + " times for " +
                                 std::to_string(counts_[0]) + " stereo pairs");
      }
    } else {
      for (int i = 0; i < counts_[0]; ++i) times_.push_back(0.1 * i);  // KITTI's 10 Hz
    }
    const cv::Mat first = ReadGrey((folder_[0] / Name(0)).string(), 0, 0, /*any_size=*/true);
    rig_.width = first.cols;
    rig_.height = first.rows;
    rig_.left = k[0];
    rig_.right = k[1];
    rig_.right_from_left = Rigid3d(Eigen::Matrix3d::Identity(), t[1] - t[0]);
    try {
      rig_.Check();
    } catch (const std::exception& e) {
      throw std::runtime_error(calib + ": unusable stereo rig: " + e.what());
    }
    const fs::path poses = ground_truth.empty() ? dir_ / "poses.txt" : fs::path(ground_truth);
    if (!ground_truth.empty() && !fs::exists(poses)) throw std::runtime_error(ground_truth + ": ground truth file missing");
    if (fs::exists(poses)) {
      ground_truth_ = ReadKittiTrajectory(poses.string());
      if (static_cast<int>(ground_truth_.size()) != counts_[0]) {
        throw std::runtime_error(poses.string() + ": " + std::to_string(ground_truth_.size()) + " poses for " +
                                 std::to_string(counts_[0]) + " stereo pairs");
      }
      for (int i = 0; i < counts_[0]; ++i) ground_truth_[i].time = times_[i];
      ground_truth_file_ = poses.string();
    }
  }
  const StereoRig& rig() const override { return rig_; }
  int size() const override { return counts_[0]; }
  double Time(int index) const override { return times_.at(index); }
  StereoImages Read(int index) const override {
    StereoImages out;
    out.time = Time(index);
    out.left = ReadGrey((folder_[0] / Name(index)).string(), rig_.width, rig_.height);
    out.right = ReadGrey((folder_[1] / Name(index)).string(), rig_.width, rig_.height);
    return out;
  }
  std::string Describe() const override {
    return "KITTI layout at " + dir_.string() + ": " + std::to_string(size()) + " stereo pairs, " +
           std::to_string(rig_.width) + " x " + std::to_string(rig_.height);
  }

 private:
  static cv::Mat ReadGrey(const std::string& path, int width, int height, bool any_size = false) {
    if (any_size) {
      if (!fs::exists(path)) throw std::runtime_error(path + ": image missing");
      const cv::Mat image = cv::imread(path, cv::IMREAD_GRAYSCALE);
      if (image.empty()) throw std::runtime_error(path + ": cannot read the image (not a PNG OpenCV can decode?)");
      return image;
    }
    return slt::ReadGrey(path, width, height);
  }
  static std::string Name(int index) {
    char name[16];
    std::snprintf(name, sizeof(name), "%06d.png", index);
    return name;
  }
  fs::path dir_, folder_[2];
  std::vector<double> times_;
  int counts_[2] = {0, 0};
  StereoRig rig_;
};

}  // namespace

const EnumNames<DatasetLayout>& DatasetLayoutNames() {
  // "euroc" after "asl": a layout is written by its first name.
  static const EnumNames<DatasetLayout> names = {{DatasetLayout::kAuto, "auto"}, {DatasetLayout::kAsl, "asl"},
                                                 {DatasetLayout::kAsl, "euroc"}, {DatasetLayout::kKitti, "kitti"}};
  return names;
}

DatasetLayout DatasetLayoutFromName(const std::string& name) {
  for (const auto& [layout, n] : DatasetLayoutNames()) {
    if (name == n) return layout;
  }
  throw std::invalid_argument("unknown dataset layout '" + name + "' (known: auto, asl, euroc, kitti)");
}

DatasetLayout DetectDatasetLayout(const std::string& path) {
  const fs::path dir(path);
  if (!fs::is_directory(dir)) throw std::runtime_error(path + ": not a folder");
  if (fs::exists(dir / "mav0" / "cam0" / "data.csv") || fs::exists(dir / "cam0" / "data.csv")) return DatasetLayout::kAsl;
  if ((fs::exists(dir / "image_0") || fs::exists(dir / "image_l")) && fs::exists(dir / "calib.txt")) {
    return DatasetLayout::kKitti;
  }
  throw std::runtime_error(path + ": neither the ASL/EuRoC layout (mav0/cam0/data.csv) nor the KITTI layout "
                                  "(image_0/ or image_l/, calib.txt) was found");
}

std::unique_ptr<StereoImageSource> OpenStereoImages(const std::string& path, DatasetLayout layout,
                                                    const std::string& ground_truth) {
  if (layout == DatasetLayout::kAuto) layout = DetectDatasetLayout(path);
  if (layout == DatasetLayout::kKitti) return std::make_unique<KittiSource>(path, ground_truth);
  return std::make_unique<AslSource>(path, ground_truth);
}

Trajectory GroundTruthFromStart(const Trajectory& world_from_cam, double start_time) {
  if (world_from_cam.empty()) return {};
  size_t nearest = 0;
  for (size_t k = 1; k < world_from_cam.size(); ++k) {
    if (std::abs(world_from_cam[k].time - start_time) < std::abs(world_from_cam[nearest].time - start_time)) nearest = k;
  }
  const Rigid3d start_from_world = world_from_cam[nearest].world_from_cam.Inverse();
  Trajectory out;
  out.reserve(world_from_cam.size());
  for (const TimedPose& pose : world_from_cam) out.push_back({pose.time, start_from_world * pose.world_from_cam});
  return out;
}

}  // namespace slt
