// The stereo images of a simulated sequence (simulator/simulator.h) and their output in EuRoC's
// ASL layout (docs/formats.md): the rasteriser (render/rasterizer.h) for the scene radiance,
// optional motion blur over the exposure, then the camera model (render/image_formation.h).
// Every image is a function of (config, frame, camera) only: its noise comes from the keyed
// "image_noise" stream (common/random.h), so images are byte-identical whatever the thread
// count or order.
#pragma once

#include <cstdint>
#include <functional>
#include <opencv2/core.hpp>
#include <string>

#include "render/rasterizer.h"
#include "simulator/simulator.h"

namespace slt {

class SequenceRenderer {
 public:
  // Keeps references to both; they must outlive the renderer.
  SequenceRenderer(const SimulatedSequence& sequence, const SimulationConfig& config);

  // The scene radiance (CV_32FC1) seen by `camera` (0 = left, 1 = right) at frame `frame`,
  // averaged over config.images.motion_blur_samples poses spread over the exposure. With lens
  // distortion (config.images.distortion), the pinhole radiance is rendered on a canvas large
  // enough for the whole distorted field of view and resampled (bilinear) at the undistorted
  // position of every pixel: pixel (u, v) sees what the pinhole camera sees at
  // K undistort(K^-1 (u, v)) (geometry/distortion.h).
  cv::Mat Radiance(int frame, int camera) const;
  // The 8-bit grey image (CV_8UC1).
  cv::Mat Image(int frame, int camera) const;
  // cam_from_world of `camera` at a fractional frame time (SE(3) interpolation between the
  // ground-truth poses of the neighbouring frames, clamped to the sequence).
  Rigid3d CamFromWorld(double frame, int camera) const;
  const SurfaceRasterizer& Rasterizer() const { return rasterizer_; }

 private:
  // The pinhole radiance of `camera` on its canvas (the image itself without distortion).
  cv::Mat PinholeRadiance(int frame, int camera) const;

  const SimulatedSequence& sequence_;
  const SimulationConfig& config_;
  SurfaceRasterizer rasterizer_;
  // With distortion, per camera: the canvas camera and size, and for every image pixel its
  // position on the canvas (CV_32FC2).
  struct Canvas {
    PinholeCamera camera;
    int width = 0, height = 0;
    cv::Mat map;
  };
  Canvas canvas_[2];
};

// Writes DIR/mav0/cam0 and cam1 (data/<timestamp_ns>.png, data.csv, sensor.yaml) and
// mav0/state_groundtruth_estimate0/data.csv, body = the left camera; the calibration is the
// tracker's rig (sequence.sequence.rig, as in seq.json). Frames are rendered on `threads`
// workers (>= 1); `progress(done, total)` is called after each frame, from one thread at a
// time. Everything is written under DIR/mav0.partial first and renamed to DIR/mav0 (replacing
// an old one) only when complete.
void WriteEurocSequence(const std::string& dir, const SimulatedSequence& sequence, const SimulationConfig& config,
                        int threads, const std::function<void(int done, int total)>& progress = nullptr);

// The same images in KITTI odometry's layout (dataset/kitti.h): DIR/image_0 and image_1
// (<000000>.png, each folder staged as <folder>.partial and swapped in whole), DIR/calib.txt
// (the tracker's rig, which must be a rectified pair: std::invalid_argument otherwise, as with
// lens distortion), DIR/times.txt and DIR/poses.txt (the left camera's ground truth).
void WriteKittiSequence(const std::string& dir, const SimulatedSequence& sequence, const SimulationConfig& config,
                        int threads, const std::function<void(int done, int total)>& progress = nullptr);

}  // namespace slt
