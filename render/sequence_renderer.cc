#include "render/sequence_renderer.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "common/file_io.h"
#include "common/parallel.h"
#include "dataset/euroc.h"
#include "dataset/kitti.h"
#include "geometry/distortion.h"
#include "geometry/se3.h"
#include "render/image_formation.h"
#include "simulator/random_draws.h"

namespace slt {

SequenceRenderer::SequenceRenderer(const SimulatedSequence& sequence, const SimulationConfig& config)
    : sequence_(sequence), config_(config), rasterizer_(sequence.surfaces) {
  const StereoRig& rig = sequence_.true_rig;
  const RadialTangential& distortion = config_.images.distortion;
  for (int camera = 0; camera < 2; ++camera) {
    Canvas& canvas = canvas_[camera];
    const PinholeCamera& k = camera == 0 ? rig.left : rig.right;
    canvas.camera = k;
    canvas.width = rig.width;
    canvas.height = rig.height;
    if (IsZero(distortion)) continue;
    cv::Mat map(rig.height, rig.width, CV_32FC2);
    double lo_u = 0.0, lo_v = 0.0, hi_u = rig.width - 1.0, hi_v = rig.height - 1.0;
    for (int v = 0; v < rig.height; ++v) {
      for (int u = 0; u < rig.width; ++u) {
        const Eigen::Vector2d pinhole =
            k.NormalizedToPixel(UndistortNormalized(k.PixelToNormalized(Eigen::Vector2d(u, v)), distortion));
        map.at<cv::Vec2f>(v, u) = cv::Vec2f(static_cast<float>(pinhole.x()), static_cast<float>(pinhole.y()));
        lo_u = std::min(lo_u, pinhole.x());
        lo_v = std::min(lo_v, pinhole.y());
        hi_u = std::max(hi_u, pinhole.x());
        hi_v = std::max(hi_v, pinhole.y());
      }
    }
    // A canvas covering every sampled position with two pixels to spare (bilinear reads one).
    const int origin_u = static_cast<int>(std::floor(lo_u)) - 2, origin_v = static_cast<int>(std::floor(lo_v)) - 2;
    canvas.width = static_cast<int>(std::ceil(hi_u)) + 3 - origin_u;
    canvas.height = static_cast<int>(std::ceil(hi_v)) + 3 - origin_v;
    canvas.camera.cx -= origin_u;
    canvas.camera.cy -= origin_v;
    map -= cv::Scalar(origin_u, origin_v);
    canvas.map = map;
  }
}

Rigid3d SequenceRenderer::CamFromWorld(double frame, int camera) const {
  const Trajectory& gt = sequence_.ground_truth;
  const double last = static_cast<double>(gt.size() - 1);
  const double tau = std::clamp(frame, 0.0, last);
  const std::size_t k0 = static_cast<std::size_t>(std::min(std::floor(tau), std::max(0.0, last - 1.0)));
  Rigid3d world_from_left = gt[k0].world_from_cam;
  const double alpha = tau - static_cast<double>(k0);
  if (alpha > 0.0 && k0 + 1 < gt.size()) {
    const Rigid3d step = gt[k0].world_from_cam.Inverse() * gt[k0 + 1].world_from_cam;
    world_from_left = world_from_left * ExpSE3(alpha * LogSE3(step));
  }
  const Rigid3d left_from_world = world_from_left.Inverse();
  return camera == 0 ? left_from_world : sequence_.true_rig.right_from_left * left_from_world;
}

cv::Mat SequenceRenderer::PinholeRadiance(int frame, int camera) const {
  const Canvas& canvas = canvas_[camera];
  const ImageConfig& images = config_.images;
  cv::Mat radiance;
  if (images.motion_blur_samples <= 1 || images.exposure_time_frames == 0.0) {
    rasterizer_.Render(canvas.camera, canvas.width, canvas.height, CamFromWorld(frame, camera), &radiance);
    return radiance;
  }
  // Poses at the middles of equal parts of the exposure, centred on the frame time: the blur is
  // symmetric about the frame's pose, so edges stay centred on the ground-truth lines.
  cv::Mat sum = cv::Mat::zeros(canvas.height, canvas.width, CV_32FC1), one;
  for (int j = 0; j < images.motion_blur_samples; ++j) {
    const double offset = ((j + 0.5) / images.motion_blur_samples - 0.5) * images.exposure_time_frames;
    rasterizer_.Render(canvas.camera, canvas.width, canvas.height, CamFromWorld(frame + offset, camera), &one);
    sum += one;
  }
  return sum / static_cast<double>(images.motion_blur_samples);
}

cv::Mat SequenceRenderer::Radiance(int frame, int camera) const {
  cv::Mat radiance = PinholeRadiance(frame, camera);
  if (canvas_[camera].map.empty()) return radiance;
  cv::Mat distorted;
  cv::remap(radiance, distorted, canvas_[camera].map, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return distorted;
}

cv::Mat SequenceRenderer::Image(int frame, int camera) const {
  const KeyedStream noise(config_.ImageSeed(), "image_noise");
  const std::uint64_t key = noise.Image(static_cast<std::uint64_t>(frame), static_cast<std::uint64_t>(camera)).At(0)();
  return FormImage(Radiance(frame, camera), config_.images, ExposureGain(config_.images, config_.ImageSeed(), frame),
                   key);
}

namespace {

// Renders every frame's two images on `threads` workers and writes them as PNG to
// path(frame, camera).
void RenderImages(const SimulatedSequence& sequence, const SimulationConfig& config, int threads,
                  const std::function<void(int done, int total)>& progress,
                  const std::function<std::string(int frame, int camera)>& path) {
  const int frames = static_cast<int>(sequence.ground_truth.size());
  const SequenceRenderer renderer(sequence, config);
  std::mutex mutex;  // guards done and the progress callback
  int done = 0;
  ParallelFor(static_cast<size_t>(frames), threads, [&](size_t k) {
    for (int camera = 0; camera < 2; ++camera) {
      const std::string file = path(static_cast<int>(k), camera);
      if (!cv::imwrite(file, renderer.Image(static_cast<int>(k), camera))) {
        throw std::runtime_error(file + ": cannot write image");
      }
    }
    const std::lock_guard<std::mutex> lock(mutex);
    ++done;
    if (progress) progress(done, frames);
  });
}

}  // namespace

void WriteEurocSequence(const std::string& dir, const SimulatedSequence& sequence, const SimulationConfig& config,
                        int threads, const std::function<void(int done, int total)>& progress) {
  namespace fs = std::filesystem;
  const fs::path final_dir = fs::path(dir) / "mav0", work = FreshStagingDir(final_dir.string());
  const char* camera_names[2] = {"cam0", "cam1"};
  for (const char* name : camera_names) fs::create_directories(work / name / "data");
  fs::create_directories(work / "state_groundtruth_estimate0");

  const int frames = static_cast<int>(sequence.ground_truth.size());
  std::vector<std::int64_t> timestamps(static_cast<std::size_t>(frames));
  for (int k = 0; k < frames; ++k) timestamps[k] = EurocTimestampNs(sequence.ground_truth[k].time);
  for (int k = 1; k < frames; ++k) {
    if (timestamps[k] <= timestamps[k - 1]) {
      throw std::invalid_argument(dir + ": frames " + std::to_string(k - 1) + " and " + std::to_string(k) +
                                  " have the same timestamp in nanoseconds (frame_rate too high)");
    }
  }

  RenderImages(sequence, config, threads, progress, [&](int k, int camera) {
    return (work / camera_names[camera] / "data" / (std::to_string(timestamps[k]) + ".png")).string();
  });

  const StereoRig& rig = sequence.sequence.rig;  // the calibration given to the tracker
  for (int camera = 0; camera < 2; ++camera) {
    EurocCameraInfo info;
    info.comment = std::string("simulated ") + (camera == 0 ? "left" : "right") + " camera (simulate --images)";
    info.body_from_cam = camera == 0 ? Rigid3d::Identity() : rig.right_from_left.Inverse();
    info.rate_hz = config.frame_rate;
    info.width = rig.width;
    info.height = rig.height;
    info.intrinsics = camera == 0 ? rig.left : rig.right;
    info.distortion = config.images.distortion;
    WriteEurocCameraYaml((work / camera_names[camera] / "sensor.yaml").string(), info);
    WriteEurocImageList((work / camera_names[camera] / "data.csv").string(), timestamps);
  }
  WriteEurocGroundTruth((work / "state_groundtruth_estimate0" / "data.csv").string(), sequence.ground_truth);
  ReplaceDirectory(work.string(), final_dir.string());
}


void WriteKittiSequence(const std::string& dir, const SimulatedSequence& sequence, const SimulationConfig& config,
                        int threads, const std::function<void(int done, int total)>& progress) {
  namespace fs = std::filesystem;
  if (!IsZero(config.images.distortion)) {
    throw std::invalid_argument(dir + ": KITTI's layout holds rectified images: images.distortion must be zero");
  }
  const StereoRig& rig = sequence.sequence.rig;  // the calibration given to the tracker
  const std::string folders[2] = {(fs::path(dir) / "image_0").string(), (fs::path(dir) / "image_1").string()};
  CreateDirectories(dir);
  // First: it refuses a rig that is not a rectified pair before any image is rendered.
  WriteKittiCalibration((fs::path(dir) / "calib.txt").string(), rig);
  const std::string work[2] = {FreshStagingDir(folders[0]), FreshStagingDir(folders[1])};
  RenderImages(sequence, config, threads, progress,
               [&](int k, int camera) { return (fs::path(work[camera]) / KittiImageName(k)).string(); });
  std::vector<double> times;
  for (const TimedPose& pose : sequence.ground_truth) times.push_back(pose.time);
  WriteKittiTimes((fs::path(dir) / "times.txt").string(), times);
  WriteKittiTrajectory((fs::path(dir) / "poses.txt").string(), sequence.ground_truth);
  for (int camera = 0; camera < 2; ++camera) ReplaceDirectory(work[camera], folders[camera]);
}

}  // namespace slt
