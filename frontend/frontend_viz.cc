#include "frontend/frontend_viz.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "common/file_io.h"
#include "common/json_reader.h"
#include "frontend/line_detection.h"
#include "frontend/line_motion.h"

namespace slt {
namespace fs = std::filesystem;
namespace {

const cv::Scalar kDetected(0, 200, 255), kTracked(0, 200, 0), kReprojected(255, 0, 255);

cv::Mat Colour(const cv::Mat& grey) {
  cv::Mat out;
  cv::cvtColor(grey, out, cv::COLOR_GRAY2BGR);
  return out;
}

void DrawSegment(cv::Mat* image, const Segment2d& s, const cv::Scalar& colour, int thickness = 1) {
  cv::line(*image, cv::Point2d(s[0], s[1]), cv::Point2d(s[2], s[3]), colour, thickness, cv::LINE_AA);
}

// The segment between two world points seen by a camera (false when one is behind it).
bool ProjectSegment(const Rigid3d& cam_from_world, const PinholeCamera& camera,
                    const std::pair<Eigen::Vector3d, Eigen::Vector3d>& ends, Segment2d* segment) {
  const Eigen::Vector3d a = cam_from_world * ends.first, b = cam_from_world * ends.second;
  if (!(a.z() > 1e-3) || !(b.z() > 1e-3)) return false;
  *segment << camera.Project(a), camera.Project(b);
  return segment->allFinite();
}

void Save(const std::string& path, const cv::Mat& image) {
  if (!cv::imwrite(path, image)) throw std::runtime_error(path + ": cannot write the picture");
}

cv::Mat SideBySide(const cv::Mat& left, const cv::Mat& right) {
  cv::Mat out;
  cv::hconcat(left, right, out);
  return out;
}

}  // namespace

FrontEndPictures::FrontEndPictures(const std::string& dir, const StereoRig& rig, int frames)
    : dir_(dir), partial_(FreshStagingDir(dir)), rig_(rig), frames_(frames) {}

void FrontEndPictures::AddFrame(int k, const cv::Mat& left, const cv::Mat& right, const StereoFrontEnd& front_end,
                                const StereoFrame& frame, const TrackerOutput& output) {
  if (k == 0) {
    cv::Mat l = Colour(left), r = Colour(right);
    for (const ImageLine& line : front_end.last_detections(0)) DrawSegment(&l, line.segment, kDetected);
    for (const ImageLine& line : front_end.last_detections(1)) DrawSegment(&r, line.segment, kDetected);
    Save(partial_ + "/detections_first_pair.png", SideBySide(l, r));
    // The reference lines: the first pair's stereo matches, triangulated.
    for (size_t i = 0; i < frame.left.size(); ++i) {
      const Eigen::Vector3d ll = NormalizedLineFromPixelLine(rig_.left, LineFromSegment(frame.left[i].segment));
      const Eigen::Vector3d rl = NormalizedLineFromPixelLine(rig_.right, LineFromSegment(frame.right[i].segment));
      if (front_end.matcher().geometry().EpipolarSine(frame.left[i].segment) < std::sin(5.0 * M_PI / 180.0)) continue;
      ReferenceLine& reference = reference_[frame.left[i].id];
      reference.line = StereoPairLine(rig_.right_from_left, ll, rl);
      Eigen::Vector3d a, b;
      if (StereoSegmentEndpoints(rig_, frame.left[i].segment, frame.right[i].segment, &a, &b)) {
        reference.ends = std::make_pair(a, b);
      }
    }
  }
  // Re-project the reference lines still tracked; angles against the tracked segments.
  const Rigid3d left_from_world = output.cam_from_world;
  const Rigid3d right_from_world = rig_.right_from_left * left_from_world;
  double sum = 0.0;
  int count = 0;
  const bool picture = k > 0 && (k == frames_ / 3 || k == (2 * frames_) / 3 || k == frames_ - 1);
  cv::Mat images[2];
  if (picture) {
    images[0] = Colour(left);
    images[1] = Colour(right);
  }
  for (size_t i = 0; i < frame.left.size(); ++i) {
    const auto it = reference_.find(frame.left[i].id);
    if (it == reference_.end()) continue;
    for (int c = 0; c < 2; ++c) {
      const PinholeCamera& camera = c == 0 ? rig_.left : rig_.right;
      const Eigen::Vector3d normalized = TransformPluecker(c == 0 ? left_from_world : right_from_world, it->second.line).moment;
      const Eigen::Vector3d pixel_line = PixelLineFromNormalizedLine(camera, normalized);
      const Segment2d& tracked = c == 0 ? frame.left[i].segment : frame.right[i].segment;
      const Eigen::Vector2d d = (tracked.tail<2>() - tracked.head<2>()).normalized();
      const Eigen::Vector2d e = Eigen::Vector2d(-pixel_line.y(), pixel_line.x()).normalized();
      sum += std::acos(std::min(1.0, std::abs(d.dot(e)))) * 180.0 / M_PI;
      ++count;
      if (picture) {
        const auto& ends = it->second.ends;
        Segment2d s;
        if (ends && ProjectSegment(c == 0 ? left_from_world : right_from_world, camera, *ends, &s) &&
            ClipSegmentToImage(rig_.width, rig_.height, &s)) {
          DrawSegment(&images[c], s, kReprojected);
        }
        DrawSegment(&images[c], tracked, kTracked, 2);
      }
    }
  }
  last_count_ = count / 2;
  last_angle_ = count > 0 ? sum / count : 0.0;
  if (count > 0) curve_.push_back({k, last_angle_, last_count_});
  if (picture) {
    char name[64];
    std::snprintf(name, sizeof(name), "/reprojection_%06d.png", k);
    Save(partial_ + name, SideBySide(images[0], images[1]));
  }
}

void FrontEndPictures::Finish() {
  std::string csv = "frame,mean_angle_deg,lines\n";
  std::vector<double> x, y;
  for (const Point& p : curve_) {
    csv += std::to_string(p.frame) + "," + std::to_string(p.angle_deg) + "," + std::to_string(p.lines) + "\n";
    x.push_back(p.frame);
    y.push_back(p.angle_deg);
  }
  WriteTextFileAtomically(JoinPath(partial_, kMarkerFile), csv);
  WriteCurvePng(partial_ + "/reprojection_error.png", x, y,
                "Re-projection error of the first pair's lines (Fig. 9)", "frame", "mean angle, deg");
  ReplaceDirectory(partial_, dir_);
}

void WriteCurvePng(const std::string& path, const std::vector<double>& x, const std::vector<double>& y,
                   const std::string& title, const std::string& x_label, const std::string& y_label) {
  const int width = 800, height = 400, left = 70, right = 20, top = 40, bottom = 50;
  cv::Mat canvas(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const double x0 = x.empty() ? 0.0 : *std::min_element(x.begin(), x.end());
  const double x1 = x.empty() ? 1.0 : std::max(x0 + 1.0, *std::max_element(x.begin(), x.end()));
  double y1 = y.empty() ? 1.0 : *std::max_element(y.begin(), y.end());
  // A round upper bound: 1, 2 or 5 times a power of ten.
  const double step = std::pow(10.0, std::floor(std::log10(std::max(y1, 1e-6))));
  y1 = y1 <= step ? step : (y1 <= 2 * step ? 2 * step : (y1 <= 5 * step ? 5 * step : 10 * step));
  const auto px = [&](double v) { return left + (v - x0) / (x1 - x0) * (width - left - right); };
  const auto py = [&](double v) { return height - bottom - v / y1 * (height - top - bottom); };
  const cv::Scalar black(0, 0, 0), grid(220, 220, 220);
  for (int i = 0; i <= 5; ++i) {
    const double v = y1 * i / 5.0;
    cv::line(canvas, cv::Point2d(left, py(v)), cv::Point2d(width - right, py(v)), grid);
    char label[32];
    std::snprintf(label, sizeof(label), "%.3g", v);
    cv::putText(canvas, label, cv::Point2d(5, py(v) + 4), cv::FONT_HERSHEY_SIMPLEX, 0.4, black);
    const double xv = x0 + (x1 - x0) * i / 5.0;
    std::snprintf(label, sizeof(label), "%.0f", xv);
    cv::putText(canvas, label, cv::Point2d(px(xv) - 10, height - bottom + 18), cv::FONT_HERSHEY_SIMPLEX, 0.4, black);
  }
  cv::rectangle(canvas, cv::Point(left, top), cv::Point(width - right, height - bottom), black);
  std::vector<cv::Point> points;
  for (size_t i = 0; i < x.size(); ++i) points.emplace_back(cvRound(px(x[i])), cvRound(py(y[i])));
  if (points.size() > 1) cv::polylines(canvas, points, false, cv::Scalar(200, 80, 0), 2, cv::LINE_AA);
  cv::putText(canvas, title, cv::Point(left, 25), cv::FONT_HERSHEY_SIMPLEX, 0.55, black, 1, cv::LINE_AA);
  cv::putText(canvas, x_label, cv::Point(width / 2, height - 12), cv::FONT_HERSHEY_SIMPLEX, 0.45, black);
  cv::putText(canvas, y_label, cv::Point(5, top - 8), cv::FONT_HERSHEY_SIMPLEX, 0.45, black);
  Save(path, canvas);
}

}  // namespace slt
