#include "frontend/image_sequence.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "dataset/euroc.h"

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

class AslSource : public StereoImageSource {
 public:
  explicit AslSource(const std::string& path) {
    const fs::path mav0 = fs::exists(fs::path(path) / "mav0") ? fs::path(path) / "mav0" : fs::path(path);
    cam_[0] = mav0 / "cam0";
    cam_[1] = mav0 / "cam1";
    EurocCameraInfo info[2];
    for (int c = 0; c < 2; ++c) {
      const std::string yaml = (cam_[c] / "sensor.yaml").string();
      info[c] = ReadEurocCameraYaml(yaml);
      for (double k : info[c].distortion) {
        if (k != 0.0) {
          throw std::runtime_error(yaml + ": key 'distortion_coefficients': non-zero distortion; the front end "
                                          "reads undistorted (rectified) images only");
        }
      }
      lists_[c] = ReadEurocImageList((cam_[c] / "data.csv").string());
    }
    if (info[0].width != info[1].width || info[0].height != info[1].height) {
      throw std::runtime_error((cam_[1] / "sensor.yaml").string() + ": key 'resolution': differs from cam0's");
    }
    if (lists_[0].size() != lists_[1].size()) {
      throw std::runtime_error((cam_[1] / "data.csv").string() + ": " + std::to_string(lists_[1].size()) +
                               " images, but " + (cam_[0] / "data.csv").string() + " lists " +
                               std::to_string(lists_[0].size()));
    }
    for (size_t k = 0; k < lists_[0].size(); ++k) {
      if (lists_[0][k].timestamp_ns != lists_[1][k].timestamp_ns) {
        throw std::runtime_error((cam_[1] / "data.csv").string() + ": image " + std::to_string(k) + " has timestamp " +
                                 std::to_string(lists_[1][k].timestamp_ns) + ", cam0's has " +
                                 std::to_string(lists_[0][k].timestamp_ns));
      }
    }
    rig_.width = info[0].width;
    rig_.height = info[0].height;
    rig_.left = info[0].intrinsics;
    rig_.right = info[1].intrinsics;
    // right_from_left = cam1_from_body * body_from_cam0.
    rig_.right_from_left = info[1].body_from_cam.Inverse() * info[0].body_from_cam;
    try {
      rig_.Check();
    } catch (const std::exception& e) {
      throw std::runtime_error((cam_[1] / "sensor.yaml").string() + ": unusable stereo rig: " + e.what());
    }
    description_ = "ASL layout at " + mav0.string();
  }
  const StereoRig& rig() const override { return rig_; }
  int size() const override { return static_cast<int>(lists_[0].size()); }
  StereoImages Read(int index) const override {
    StereoImages out;
    out.time = lists_[0].at(index).timestamp_ns * 1e-9;
    out.left = ReadGrey((cam_[0] / "data" / lists_[0][index].filename).string(), rig_.width, rig_.height);
    out.right = ReadGrey((cam_[1] / "data" / lists_[1][index].filename).string(), rig_.width, rig_.height);
    return out;
  }
  std::string Describe() const override {
    return description_ + ": " + std::to_string(size()) + " stereo pairs, " + std::to_string(rig_.width) + " x " +
           std::to_string(rig_.height);
  }

 private:
  fs::path cam_[2];
  std::vector<EurocImageEntry> lists_[2];
  StereoRig rig_;
  std::string description_;
};

// KITTI odometry: calib.txt has "P0: 12 numbers" (3 x 4, row-major) per camera; the images are
// rectified, P_i = K_i [I | t_i], so right_from_left = (I, t_1 - t_0).
class KittiSource : public StereoImageSource {
 public:
  explicit KittiSource(const std::string& path) : dir_(path) {
    const std::string calib = (dir_ / "calib.txt").string();
    std::ifstream in(calib);
    if (!in) throw std::runtime_error(calib + ": cannot read the calibration");
    Eigen::Matrix<double, 3, 4> p[2];
    bool found[2] = {false, false};
    for (std::string line; std::getline(in, line);) {
      std::istringstream fields(line);
      std::string key;
      fields >> key;
      for (int c = 0; c < 2; ++c) {
        if (key != "P" + std::to_string(c) + ":") continue;
        for (int i = 0; i < 12; ++i) {
          if (!(fields >> p[c](i / 4, i % 4))) throw std::runtime_error(calib + ": key '" + key + "': expected 12 numbers");
        }
        found[c] = true;
      }
    }
    for (int c = 0; c < 2; ++c) {
      if (!found[c]) throw std::runtime_error(calib + ": missing key 'P" + std::to_string(c) + ":'");
    }
    PinholeCamera k[2];
    Eigen::Vector3d t[2];
    for (int c = 0; c < 2; ++c) {
      k[c] = PinholeCamera{p[c](0, 0), p[c](1, 1), p[c](0, 2), p[c](1, 2)};
      if (std::abs(p[c](0, 1)) > 1e-9 || std::abs(p[c](1, 0)) > 1e-9 || std::abs(p[c](2, 2) - 1.0) > 1e-9) {
        throw std::runtime_error(calib + ": key 'P" + std::to_string(c) + ":': not a rectified K [I | t]");
      }
      t[c] = k[c].K().inverse() * p[c].col(3);
    }
    const std::string times = (dir_ / "times.txt").string();
    std::ifstream tin(times);
    if (!tin) throw std::runtime_error(times + ": cannot read the frame times");
    for (double value; tin >> value;) times_.push_back(value);
    for (int c = 0; c < 2; ++c) {
      const fs::path folder = dir_ / ("image_" + std::to_string(c));
      int count = 0;
      while (fs::exists(folder / Name(count))) ++count;
      counts_[c] = count;
    }
    if (counts_[0] != counts_[1]) {
      throw std::runtime_error((dir_ / "image_1").string() + ": " + std::to_string(counts_[1]) + " images, but " +
                               (dir_ / "image_0").string() + " has " + std::to_string(counts_[0]));
    }
    if (static_cast<int>(times_.size()) != counts_[0]) {
      throw std::runtime_error(times + ": " + std::to_string(times_.size()) + " times for " +
                               std::to_string(counts_[0]) + " stereo pairs");
    }
    if (counts_[0] == 0) throw std::runtime_error((dir_ / "image_0").string() + ": no image 000000.png");
    const cv::Mat first = cv::imread((dir_ / "image_0" / Name(0)).string(), cv::IMREAD_GRAYSCALE);
    if (first.empty()) throw std::runtime_error((dir_ / "image_0" / Name(0)).string() + ": cannot read the image");
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
  }
  const StereoRig& rig() const override { return rig_; }
  int size() const override { return counts_[0]; }
  StereoImages Read(int index) const override {
    StereoImages out;
    out.time = times_.at(index);
    out.left = ReadGrey((dir_ / "image_0" / Name(index)).string(), rig_.width, rig_.height);
    out.right = ReadGrey((dir_ / "image_1" / Name(index)).string(), rig_.width, rig_.height);
    return out;
  }
  std::string Describe() const override {
    return "KITTI layout at " + dir_.string() + ": " + std::to_string(size()) + " stereo pairs, " +
           std::to_string(rig_.width) + " x " + std::to_string(rig_.height);
  }

 private:
  static std::string Name(int index) {
    char name[16];
    std::snprintf(name, sizeof(name), "%06d.png", index);
    return name;
  }
  fs::path dir_;
  std::vector<double> times_;
  int counts_[2] = {0, 0};
  StereoRig rig_;
};

}  // namespace

const EnumNames<DatasetLayout>& DatasetLayoutNames() {
  static const EnumNames<DatasetLayout> names = {
      {DatasetLayout::kAuto, "auto"}, {DatasetLayout::kAsl, "asl"}, {DatasetLayout::kKitti, "kitti"}};
  return names;
}

DatasetLayout DatasetLayoutFromName(const std::string& name) {
  if (name == "euroc") return DatasetLayout::kAsl;
  for (const auto& [layout, n] : DatasetLayoutNames()) {
    if (name == n) return layout;
  }
  throw std::invalid_argument("unknown dataset layout '" + name + "' (known: auto, asl, euroc, kitti)");
}

DatasetLayout DetectDatasetLayout(const std::string& path) {
  const fs::path dir(path);
  if (!fs::is_directory(dir)) throw std::runtime_error(path + ": not a folder");
  if (fs::exists(dir / "mav0" / "cam0" / "data.csv") || fs::exists(dir / "cam0" / "data.csv")) return DatasetLayout::kAsl;
  if (fs::exists(dir / "image_0") && fs::exists(dir / "calib.txt")) return DatasetLayout::kKitti;
  throw std::runtime_error(path + ": neither the ASL/EuRoC layout (mav0/cam0/data.csv) nor the KITTI layout "
                                  "(image_0/, calib.txt) was found");
}

std::unique_ptr<StereoImageSource> OpenStereoImages(const std::string& path, DatasetLayout layout) {
  if (layout == DatasetLayout::kAuto) layout = DetectDatasetLayout(path);
  if (layout == DatasetLayout::kKitti) return std::make_unique<KittiSource>(path);
  return std::make_unique<AslSource>(path);
}

}  // namespace slt
