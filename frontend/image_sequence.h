// Stereo image sequences on disk, behind one interface so that the front end reads rendered and
// real data through one path. Layouts (docs/formats.md, docs/datasets.md):
//   asl    EuRoC's ASL folder (EuRoC MAV, and what `simulate --images` writes):
//          DIR/mav0/cam0|cam1/data.csv, data/<timestamp>.png, sensor.yaml (DIR may also be the
//          mav0 folder itself). Left and right images are paired by equal timestamps; an image
//          listed for one camera only is skipped (EuRoC's lists sometimes differ by a few frames).
//          Distorted or unrectified pairs are undistorted and rectified
//          (frontend/stereo_rectification.h): rig() is then the rectified rig. Ground truth:
//          mav0/state_groundtruth_estimate0/data.csv, else DIR/groundtruth_body.tum (both of the
//          body frame, converted to the left camera with cam0's T_BS).
//   kitti  KITTI odometry: DIR/image_0|image_1 (or image_l|image_r)/<000000>.png, calib.txt (P0,
//          P1 of the rectified pair; the baseline from P1), times.txt (else 10 Hz), poses.txt
//          (ground truth of the left camera, when present).
// `auto` picks the layout from the files present. Images are 8-bit grey (colour PNGs are
// converted). Every error names the file: a missing or unreadable image, image folders of
// different lengths, times out of order, an image of the wrong size, a bad calibration or
// ground truth.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "common/options.h"
#include "dataset/trajectory.h"
#include "geometry/camera.h"

namespace slt {

enum class DatasetLayout { kAuto, kAsl, kKitti };
const EnumNames<DatasetLayout>& DatasetLayoutNames();  // "auto", "asl", "euroc" (= asl), "kitti"
// Throws std::invalid_argument listing the names.
DatasetLayout DatasetLayoutFromName(const std::string& name);

struct StereoImages {
  double time = 0.0;  // seconds
  cv::Mat left, right;  // CV_8UC1, rectified when the source rectifies
};

class StereoImageSource {
 public:
  virtual ~StereoImageSource() = default;
  // The rig of the images Read() returns (the rectified rig when the source rectifies).
  virtual const StereoRig& rig() const = 0;
  virtual int size() const = 0;  // stereo pairs
  // Reads pair `index` (0 .. size()-1); std::runtime_error naming the file on failure.
  virtual StereoImages Read(int index) const = 0;
  // The time of pair `index` without reading it.
  virtual double Time(int index) const = 0;
  // "ASL layout at DIR: 300 stereo pairs, 752 x 480, undistorted and rectified".
  virtual std::string Describe() const = 0;

  // Ground truth of rig()'s left camera, world_from_cam in the dataset's world (KITTI: the
  // first left camera; EuRoC: the motion-capture world); empty when the dataset has none.
  const Trajectory& ground_truth() const { return ground_truth_; }
  const std::string& ground_truth_file() const { return ground_truth_file_; }

 protected:
  Trajectory ground_truth_;
  std::string ground_truth_file_;
};

// The layout found at `path` (std::runtime_error when none).
DatasetLayout DetectDatasetLayout(const std::string& path);
// `ground_truth` overrides the dataset's own ground truth file: for ASL a TUM file or an EuRoC
// state_groundtruth_estimate0/data.csv of the body frame, for KITTI a poses.txt.
std::unique_ptr<StereoImageSource> OpenStereoImages(const std::string& path, DatasetLayout layout = DatasetLayout::kAuto,
                                                    const std::string& ground_truth = "");

// The ground truth re-expressed with the world at its pose nearest in time to `start_time`
// (the frame a tracker starts from, whose estimate is the identity), so that an estimate and
// the ground truth compare without alignment. When the ground truth starts well after
// start_time (EuRoC's excerpt: 4.3 s later) that pose is not the start frame's: compare with
// an alignment then (evaluate --align se3). Empty in, empty out.
Trajectory GroundTruthFromStart(const Trajectory& world_from_cam, double start_time);

}  // namespace slt
