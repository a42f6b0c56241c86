#include "frontend/stereo_frontend.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace slt {
namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

StereoFrontEnd::StereoFrontEnd(const FrontEndOptions& options, const StereoRig& rig)
    : options_(options),
      rig_(rig),
      detector_(MakeLineDetector(options.detection)),
      matcher_(options.matching, rig),
      flow_{LineFlowTracker(options.tracking, 1), LineFlowTracker(options.tracking, 2)} {}

const StereoFrame& StereoFrontEnd::Process(const cv::Mat& left, const cv::Mat& right, double time,
                                           bool detect_new_lines) {
  for (const cv::Mat* image : {&left, &right}) {
    if (image->type() != CV_8UC1 || image->cols != rig_.width || image->rows != rig_.height) {
      throw std::invalid_argument("front end: expected 8-bit grey images of " + std::to_string(rig_.width) + " x " +
                                  std::to_string(rig_.height) + ", got " + std::to_string(image->cols) + " x " +
                                  std::to_string(image->rows) + " with " + std::to_string(image->channels()) +
                                  " channel(s)");
    }
  }
  stats_ = FrontEndFrameStats();
  const Clock::time_point t0 = Clock::now();
  flow_[0].BuildPyramid(left, &current_[0]);
  flow_[1].BuildPyramid(right, &current_[1]);
  stats_.times.track += Since(t0);
  if (started_) Track(left, right);
  if (detect_new_lines || !started_) Detect(left, right);
  started_ = true;
  std::swap(previous_[0], current_[0]);
  std::swap(previous_[1], current_[1]);

  frame_.time = time;
  frame_.left.resize(live_.size());
  frame_.right.resize(live_.size());
  for (size_t i = 0; i < live_.size(); ++i) {
    frame_.left[i] = {live_[i].id, live_[i].left};
    frame_.right[i] = {live_[i].id, live_[i].right};
  }
  stats_.live = static_cast<int>(live_.size());
  return frame_;
}

void StereoFrontEnd::Track(const cv::Mat& left, const cv::Mat& right) {
  (void)left;
  (void)right;
  const int n = static_cast<int>(live_.size());
  for (int c = 0; c < 2; ++c) {
    segments_[c].resize(n);
    for (int i = 0; i < n; ++i) segments_[c][i] = c == 0 ? live_[i].left : live_[i].right;
  }
  Clock::time_point t0 = Clock::now();
  for (int c = 0; c < 2; ++c) flow_[c].Flow(previous_[c], current_[c], segments_[c]);
  stats_.times.track += Since(t0);

  t0 = Clock::now();
  for (int c = 0; c < 2; ++c) flow_[c].Refit(rig_.width, rig_.height, &tracked_[c], &ok_[c]);
  const StereoGeometry& geometry = matcher_.geometry();
  const double epipolar_sine = std::sin(options_.matching.epipolar_angle_deg * M_PI / 180.0);
  int kept = 0;
  for (int i = 0; i < n; ++i) {
    if (!ok_[0][i] || !ok_[1][i]) continue;  // lost in one image: dropped in both
    const Segment2d& l = tracked_[0][i];
    const Segment2d& r = tracked_[1][i];
    if (geometry.BeamOverlap(l, r, epipolar_sine, options_.matching.epipolar_distance_px) <
            options_.tracking.min_stereo_overlap ||
        !geometry.DisparityInRange(l, r, options_.matching.min_disparity_px, options_.matching.max_disparity_px)) {
      continue;
    }
    live_[kept] = {live_[i].id, l, r};
    ++kept;
  }
  stats_.tracked = kept;
  stats_.lost = n - kept;
  live_.resize(kept);
  stats_.times.filter += Since(t0);
}

bool StereoFrontEnd::DuplicatesLiveLine(const Segment2d& left) const {
  const Eigen::Vector2d a = left.head<2>(), b = left.tail<2>();
  const Eigen::Vector2d d = (b - a).normalized();
  const double cos_max = std::cos(options_.duplicate_angle_deg * M_PI / 180.0);
  const double length = (b - a).norm();
  for (const LiveLine& live : live_) {
    const Eigen::Vector2d p = live.left.head<2>(), q = live.left.tail<2>();
    const Eigen::Vector2d e = (q - p).normalized();
    if (std::abs(d.dot(e)) < cos_max) continue;
    const Eigen::Vector2d n(-e.y(), e.x());
    if (std::abs(n.dot(a - p)) > options_.duplicate_distance_px || std::abs(n.dot(b - p)) > options_.duplicate_distance_px) {
      continue;
    }
    const double t0 = d.dot(p - a), t1 = d.dot(q - a);
    if (std::max(t0, t1) > 0.0 && std::min(t0, t1) < length) return true;
  }
  return false;
}

void StereoFrontEnd::Detect(const cv::Mat& left, const cv::Mat& right) {
  stats_.detected = true;
  Clock::time_point t0 = Clock::now();
  detections_[0] = DetectLines(*detector_, options_.detection, left);
  detections_[1] = DetectLines(*detector_, options_.detection, right);
  stats_.detected_left = static_cast<int>(detections_[0].size());
  stats_.detected_right = static_cast<int>(detections_[1].size());
  stats_.times.detect += Since(t0);

  t0 = Clock::now();
  for (int c = 0; c < 2; ++c) {
    msld_.SetImage(c == 0 ? left : right);
    descriptors_[c].resize(detections_[c].size());
    for (size_t i = 0; i < detections_[c].size(); ++i) msld_.Compute(detections_[c][i].segment, &descriptors_[c][i]);
  }
  stats_.times.describe += Since(t0);

  t0 = Clock::now();
  matcher_.Match(left, right, detections_[0], descriptors_[0], detections_[1], descriptors_[1], &matches_);
  stats_.matched = static_cast<int>(matches_.size());
  // Longest first, so that max_new_lines keeps the best-conditioned lines.
  std::sort(matches_.begin(), matches_.end(), [&](const StereoMatch& x, const StereoMatch& y) {
    return detections_[0][x.left].Length() > detections_[0][y.left].Length();
  });
  const size_t live_before = live_.size();
  for (const StereoMatch& m : matches_) {
    if (options_.max_new_lines > 0 && static_cast<int>(live_.size() - live_before) >= options_.max_new_lines) break;
    const Segment2d& l = detections_[0][m.left].segment;
    if (DuplicatesLiveLine(l)) continue;
    live_.push_back({next_id_++, l, detections_[1][m.right].segment});
  }
  stats_.added = static_cast<int>(live_.size() - live_before);
  stats_.times.match += Since(t0);
}

}  // namespace slt
