// Stereo image sequences on disk, behind one interface so that the front end reads rendered and
// real data through one path. Layouts (docs/formats.md):
//   asl    EuRoC's ASL folder (what `simulate --images` writes): DIR/mav0/cam0|cam1/data.csv,
//          data/<timestamp>.png, sensor.yaml (DIR may also be the mav0 folder itself);
//   kitti  KITTI odometry: DIR/image_0|image_1/<000000>.png, calib.txt (P0, P1), times.txt.
// `auto` picks the layout from the files present. Images are 8-bit grey (colour PNGs are
// converted). Every error names the file: a missing or unreadable image, image lists of
// different lengths or timestamps, an image of the wrong size, a bad calibration.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "common/options.h"
#include "geometry/camera.h"

namespace slt {

enum class DatasetLayout { kAuto, kAsl, kKitti };
const EnumNames<DatasetLayout>& DatasetLayoutNames();  // "auto", "asl" (also "euroc"), "kitti"
// Throws std::invalid_argument listing the names.
DatasetLayout DatasetLayoutFromName(const std::string& name);

struct StereoImages {
  double time = 0.0;  // seconds
  cv::Mat left, right;  // CV_8UC1
};

class StereoImageSource {
 public:
  virtual ~StereoImageSource() = default;
  virtual const StereoRig& rig() const = 0;
  virtual int size() const = 0;  // stereo pairs
  // Reads pair `index` (0 .. size()-1); std::runtime_error naming the file on failure.
  virtual StereoImages Read(int index) const = 0;
  // "ASL layout at DIR: 300 stereo pairs, 752 x 480".
  virtual std::string Describe() const = 0;
};

// The layout found at `path` (std::runtime_error when none).
DatasetLayout DetectDatasetLayout(const std::string& path);
std::unique_ptr<StereoImageSource> OpenStereoImages(const std::string& path, DatasetLayout layout = DatasetLayout::kAuto);

}  // namespace slt
