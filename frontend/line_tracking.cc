#include "frontend/line_tracking.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <limits>
#include <cmath>
#include <opencv2/video/tracking.hpp>

#include "frontend/line_detection.h"

namespace slt {
namespace {

// Total least-squares line through points (unit normal, a x + b y + c = 0).
bool FitLine(const std::vector<Eigen::Vector2d>& points, const int* indices, int count, Eigen::Vector3d* line) {
  if (count < 2) return false;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (int i = 0; i < count; ++i) mean += points[indices ? indices[i] : i];
  mean /= count;
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector2d d = points[indices ? indices[i] : i] - mean;
    scatter += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
  const Eigen::Vector2d normal = eig.eigenvectors().col(0);
  if (eig.eigenvalues()(1) <= 1e-12) return false;
  *line = Eigen::Vector3d(normal.x(), normal.y(), -normal.dot(mean));
  return true;
}

// The RANSAC estimator of a 2-D line from tracked points (optim/ransac.h's concept).
struct LineEstimator : FixedSampleSize<2> {
  using Model = Eigen::Vector3d;
  const std::vector<Eigen::Vector2d>* points;
  double threshold_sq;
  int NumData() const { return static_cast<int>(points->size()); }
  void MinimalSolve(const int* sample, int, std::vector<Model>* models) const {
    const Eigen::Vector2d& a = (*points)[sample[0]];
    const Eigen::Vector2d& b = (*points)[sample[1]];
    const Eigen::Vector2d d = b - a;
    const double n = d.norm();
    if (n < 1e-6) return;
    const Eigen::Vector2d normal(-d.y() / n, d.x() / n);
    models->emplace_back(normal.x(), normal.y(), -normal.dot(a));
  }
  bool Cost(int datum, const Model& line, double* cost) const {
    const double r = line.head<2>().dot((*points)[datum]) + line.z();
    *cost = r * r;
    return true;
  }
  double Threshold(int) const { return threshold_sq; }
  bool LocalOptimize(const std::vector<int>& inliers, Model* model) const {
    return FitLine(*points, inliers.data(), static_cast<int>(inliers.size()), model);
  }
};

// The derivative (du, dv) of a CV_16SC2 image, bilinear between pixel (u0, v0) and its
// neighbours (which must be inside the image) at the fractions (fu, fv).
inline Eigen::Vector2f BilinearDerivative(const cv::Mat& derivatives, int u0, int v0, float fu, float fv) {
  const short* r0 = derivatives.ptr<short>(v0) + 2 * u0;
  const short* r1 = r0 + derivatives.step1();
  const float w00 = (1 - fu) * (1 - fv), w01 = fu * (1 - fv), w10 = (1 - fu) * fv, w11 = fu * fv;
  return {w00 * r0[0] + w01 * r0[2] + w10 * r1[0] + w11 * r1[2], w00 * r0[1] + w01 * r0[3] + w10 * r1[1] + w11 * r1[3]};
}

// The derivative (du, dv) at a sub-pixel position of a CV_16SC2 image, bilinear, clamped to
// the image.
inline Eigen::Vector2f SampleDerivative(const cv::Mat& derivatives, float u, float v) {
  const int w = derivatives.cols, h = derivatives.rows;
  u = std::clamp(u, 0.0f, static_cast<float>(w - 1));
  v = std::clamp(v, 0.0f, static_cast<float>(h - 1));
  const int u0 = std::min(static_cast<int>(u), w - 2), v0 = std::min(static_cast<int>(v), h - 2);
  return BilinearDerivative(derivatives, u0, v0, u - u0, v - v0);
}

// OpenCV's Scharr derivatives in the flow pyramid are 32 x the grey-level gradient.
constexpr float kScharrScale = 32.0f;
constexpr int kMaxSnapRadius = 20;  // TrackingOptions' range
constexpr double kSnapEndMarginPx = 3.0;

// The gradient (du, dv) projected on (gx, gy) (a unit normal pre-scaled by 1 / kScharrScale),
// grey levels per px, at a sub-pixel position.
inline float GradientAlong(const cv::Mat& derivatives, const Eigen::Vector2d& x, float gx, float gy) {
  const Eigen::Vector2f grad = SampleDerivative(derivatives, static_cast<float>(x.x()), static_cast<float>(x.y()));
  return gx * grad.x() + gy * grad.y();
}

// Whether x lies on an edge: the gradient across it (projected on (gx, gy), of the polarity
// `sign`) is at least min_gradient and not below that 1 px to either side along `step`.
inline bool OnEdge(const cv::Mat& derivatives, const Eigen::Vector2d& x, const Eigen::Vector2d& step, float gx, float gy,
                   float sign, double min_gradient) {
  float g[3];
  for (int o = -1; o <= 1; ++o) g[o + 1] = sign * GradientAlong(derivatives, x + o * step, gx, gy);
  return g[1] >= min_gradient && g[1] >= g[0] && g[1] >= g[2];
}

}  // namespace

bool SnapSegmentToEdges(const TrackingOptions& options, const cv::Mat& derivatives, Segment2d* segment,
                        SnapWorkspace* workspace, double* direction_sigma_deg) {
  const Eigen::Vector2d a = segment->head<2>(), b = segment->tail<2>();
  const double length = (b - a).norm();
  if (length < 1e-6 || derivatives.type() != CV_16SC2) return false;
  const Eigen::Vector2d d = (b - a) / length, n(-d.y(), d.x());
  const int radius = std::min(kMaxSnapRadius, static_cast<int>(std::ceil(options.snap_radius_px)));
  // The places keep off the endpoints, where the edge that meets this one at a corner is within
  // reach of the derivative kernel and the image's blur.
  const double margin = std::min(kSnapEndMarginPx, 0.25 * length), span = length - 2.0 * margin;
  const int places = std::clamp(static_cast<int>(std::lround(span / options.snap_spacing_px)), 1, options.snap_max_places);
  const int width = 2 * radius + 3;  // offsets -radius-1 .. radius+1
  // Place m's distance along the segment from its first endpoint.
  const auto along = [&](int m) { return margin + (m + 0.5) * span / places; };
  // profiles[m * width + o + radius + 1] = g_m(o), grey levels per px.
  std::vector<float>& profiles = workspace->profiles;
  std::vector<Eigen::Vector2d>* edge_points = &workspace->edge_points;
  profiles.resize(static_cast<size_t>(places) * width);
  // g = grad . n / 32 (kScharrScale): the normal pre-scaled.
  const float nx = static_cast<float>(n.x()), ny = static_cast<float>(n.y());
  const float gx = nx / kScharrScale, gy = ny / kScharrScale;
  const float max_u = static_cast<float>(derivatives.cols - 2), max_v = static_cast<float>(derivatives.rows - 2);
  double polarity = 0.0;
  for (int m = 0; m < places; ++m) {
    const Eigen::Vector2d x = a + along(m) * d;
    const float u_first = static_cast<float>(x.x()) - (radius + 1) * nx, v_first = static_cast<float>(x.y()) - (radius + 1) * ny;
    const float u_last = u_first + (width - 1) * nx, v_last = v_first + (width - 1) * ny;
    float* g = &profiles[static_cast<size_t>(m) * width];
    if (std::min(u_first, u_last) >= 0.0f && std::min(v_first, v_last) >= 0.0f && std::max(u_first, u_last) < max_u &&
        std::max(v_first, v_last) < max_v) {
      // Inside: bilinear without clamping, the common case.
      for (int k = 0; k < width; ++k) {
        const float u = u_first + k * nx, v = v_first + k * ny;
        const int u0 = static_cast<int>(u), v0 = static_cast<int>(v);
        const Eigen::Vector2f grad = BilinearDerivative(derivatives, u0, v0, u - u0, v - v0);
        g[k] = gx * grad.x() + gy * grad.y();
      }
    } else {
      for (int k = 0; k < width; ++k) {
        const Eigen::Vector2f grad = SampleDerivative(derivatives, u_first + k * nx, v_first + k * ny);
        g[k] = gx * grad.x() + gy * grad.y();
      }
    }
    polarity += g[radius] + g[radius + 1] + g[radius + 2];  // |o| <= 1
  }
  const float sign = polarity >= 0.0 ? 1.0f : -1.0f;
  edge_points->clear();
  for (int m = 0; m < places; ++m) {
    const float* g = &profiles[static_cast<size_t>(m) * width] + radius + 1;  // g[o], |o| <= radius + 1
    int best = 0;
    for (int o = -radius; o <= radius; ++o) {
      if (sign * g[o] > sign * g[best]) best = o;
    }
    if (best == -radius || best == radius || sign * g[best] < options.snap_min_gradient) continue;
    const float gm = sign * g[best - 1], g0 = sign * g[best], gp = sign * g[best + 1];
    const float curvature = gm - 2.0f * g0 + gp;
    const double delta = curvature < 0.0f ? std::clamp(0.5f * (gm - gp) / curvature, -0.5f, 0.5f) : 0.0f;
    edge_points->push_back(a + along(m) * d + (best + delta) * n);
  }
  const int needed = std::max(3, static_cast<int>(std::ceil(options.snap_min_fraction * places)));
  if (static_cast<int>(edge_points->size()) < needed) return false;
  Eigen::Vector3d line;
  if (!FitLine(*edge_points, nullptr, static_cast<int>(edge_points->size()), &line)) return false;
  for (int pass = 0; pass < 2; ++pass) {
    int kept = 0;
    for (const Eigen::Vector2d& p : *edge_points) {
      if (std::abs(line.head<2>().dot(p) + line.z()) <= options.snap_inlier_px) (*edge_points)[kept++] = p;
    }
    edge_points->resize(kept);
    if (kept < needed || !FitLine(*edge_points, nullptr, kept, &line)) return false;
  }
  if (direction_sigma_deg != nullptr) {
    // The fitted direction's standard error, sigma_theta = rms / sqrt(sum (t - mean t)^2): a
    // short segment or scattered edge points leave it undetermined.
    const Eigen::Vector2d dir(line.y(), -line.x());
    double residual_sq = 0.0, st = 0.0, stt = 0.0;
    for (const Eigen::Vector2d& x : *edge_points) {
      const double r = line.head<2>().dot(x) + line.z(), t = dir.dot(x);
      residual_sq += r * r;
      st += t;
      stt += t * t;
    }
    const double count = static_cast<double>(edge_points->size());
    const double spread = stt - st * st / count;
    const double sigma = spread > 0.0 ? std::sqrt(residual_sq / std::max(1.0, count - 2.0) / spread)
                                      : std::numeric_limits<double>::infinity();
    *direction_sigma_deg = sigma * 180.0 / M_PI;
  }
  const Eigen::Vector2d normal = line.head<2>();
  Eigen::Vector2d p = a - (normal.dot(a) + line.z()) * normal, q = b - (normal.dot(b) + line.z()) * normal;
  // Trimmed to the extent of the edge on the fitted line (plus the margin and half a place):
  // an end the flow carried past the edge's end does not grow the segment. A place is on the
  // edge when the gradient at its projection onto the line is at least snap_min_gradient and
  // not below that 1 px to either side (a place whose search missed the edge because the
  // refitted line was off by more than the radius there counts, once the fit is right).
  const Eigen::Vector2d e = (q - p).normalized(), en(-e.y(), e.x());
  const auto on_edge = [&](int m) {
    return OnEdge(derivatives, p + along(m) * e, en, gx, gy, sign, options.snap_min_gradient);
  };
  int first = 0, last = places - 1;
  while (first <= last && !on_edge(first)) ++first;
  while (last > first && !on_edge(last)) --last;
  if (first > last) return false;
  const double slack = margin + 0.5 * span / places, extent = (q - p).norm();
  const double t0 = std::max(0.0, along(first) - slack);
  const double t1 = std::min(extent, along(last) + slack);
  q = p + t1 * e;
  p = p + t0 * e;
  *segment = Segment2d(p.x(), p.y(), q.x(), q.y());
  return true;
}

void ExtendAlongEdge(const TrackingOptions& options, const cv::Mat& derivatives, Segment2d* segment) {
  if (options.extend_max_px <= 0.0 || derivatives.type() != CV_16SC2) return;
  const Eigen::Vector2d a = segment->head<2>(), b = segment->tail<2>();
  const double length = (b - a).norm();
  if (length < 1e-6) return;
  const Eigen::Vector2d d = (b - a) / length, n(-d.y(), d.x());
  const float gx = static_cast<float>(n.x()) / kScharrScale, gy = static_cast<float>(n.y()) / kScharrScale;
  // The edge's polarity and strength: the gradient across the segment at its quarter points.
  float strength = 0.0f;
  for (const double f : {0.25, 0.5, 0.75}) strength += GradientAlong(derivatives, a + f * (b - a), gx, gy) / 3.0f;
  const float sign = strength >= 0.0f ? 1.0f : -1.0f;
  // The edge continues where it has at least half that strength (image noise alone passes
  // snap_min_gradient here and there beyond an edge's end).
  const double min_gradient = std::max(options.snap_min_gradient, 0.5 * std::abs(strength));
  const double margin = std::min(kSnapEndMarginPx, 0.25 * length), step = options.snap_spacing_px;
  const double max_u = derivatives.cols - 1.0, max_v = derivatives.rows - 1.0;
  const auto inside = [&](const Eigen::Vector2d& x) { return x.x() >= 0.0 && x.y() >= 0.0 && x.x() <= max_u && x.y() <= max_v; };
  // End `end` grows along the unit direction `out` by t while the place t beyond the last
  // place the snap could use (end - margin out) is on the edge.
  const auto grow = [&](const Eigen::Vector2d& end, const Eigen::Vector2d& out) {
    double reached = 0.0;
    for (double t = step; t <= options.extend_max_px && inside(end + t * out); t += step) {
      if (!OnEdge(derivatives, end + (t - margin) * out, n, gx, gy, sign, min_gradient)) break;
      reached = t;
    }
    return Eigen::Vector2d(end + reached * out);
  };
  const Eigen::Vector2d new_a = grow(a, -d), new_b = grow(b, d);
  *segment = Segment2d(new_a.x(), new_a.y(), new_b.x(), new_b.y());
}

void SnapDetections(const TrackingOptions& options, double min_length_px, const cv::Mat& derivatives,
                    std::vector<ImageLine>* lines, SnapWorkspace* workspace) {
  if (options.snap_radius_px <= 0.0) return;  // the snap is off: detections stay as detected
  // No direction test here: a detection's direction is checked where it is tracked (the test
  // is the tracker's loss test, DirectionUndetermined).
  const double min_sq = min_length_px * min_length_px;
  size_t kept = 0;
  for (ImageLine& line : *lines) {
    if (!SnapSegmentToEdges(options, derivatives, &line.segment, workspace)) continue;
    if ((line.segment.tail<2>() - line.segment.head<2>()).squaredNorm() < min_sq) continue;
    (*lines)[kept++] = line;
  }
  lines->resize(kept);
}

LineFlowTracker::LineFlowTracker(const TrackingOptions& options, std::uint64_t seed)
    : options_(options), ransac_(seed) {}

void LineFlowTracker::BuildPyramid(const cv::Mat& grey, ImagePyramid* pyramid, int levels) const {
  cv::buildOpticalFlowPyramid(grey, *pyramid, cv::Size(options_.window_px, options_.window_px),
                              std::max(options_.pyramid_levels, levels), true);
}

void LineFlowTracker::SamplePoints(const std::vector<Segment2d>& segments) {
  segments_ = segments;
  first_point_.assign(1, 0);
  points_.clear();
  for (const Segment2d& s : segments) {
    const double length = (s.tail<2>() - s.head<2>()).norm();
    const int k = std::clamp(static_cast<int>(std::lround(length / options_.point_spacing_px)) + 1,
                             options_.min_points, options_.max_points);
    for (int i = 0; i < k; ++i) {
      const double f = static_cast<double>(i) / (k - 1);
      points_.emplace_back(static_cast<float>(s[0] + f * (s[2] - s[0])), static_cast<float>(s[1] + f * (s[3] - s[1])));
    }
    first_point_.push_back(static_cast<int>(points_.size()));
  }
}

void LineFlowTracker::RunLucasKanade(const ImagePyramid& previous, const ImagePyramid& next, int levels, int flags) {
  derivatives_ = next.size() > 1 ? next[1] : cv::Mat();
  if (points_.empty()) {
    tracked_points_.clear();
    status_.clear();
    return;
  }
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, options_.max_iterations,
                                  options_.epsilon_px);
  cv::calcOpticalFlowPyrLK(previous, next, points_, tracked_points_, status_, error_,
                           cv::Size(options_.window_px, options_.window_px), levels, criteria, flags);
}

void LineFlowTracker::Flow(const ImagePyramid& previous, const ImagePyramid& next,
                           const std::vector<Segment2d>& segments) {
  SamplePoints(segments);
  RunLucasKanade(previous, next, options_.pyramid_levels, 0);
}

void LineFlowTracker::Flow(const ImagePyramid& previous, const ImagePyramid& next,
                           const std::vector<Segment2d>& segments, const std::vector<Eigen::Matrix3d>& point_maps,
                           int levels) {
  SamplePoints(segments);
  // The image size, from the pyramid's first level (which holds the image inside a border).
  const cv::Size size = next.empty() ? cv::Size() : next[0].size();
  tracked_points_.resize(points_.size());
  for (size_t s = 0; s < segments.size(); ++s) {
    const Eigen::Matrix3d& h = point_maps[s];
    for (int p = first_point_[s]; p < first_point_[s + 1]; ++p) {
      const Eigen::Vector3d q = h * Eigen::Vector3d(points_[p].x, points_[p].y, 1.0);
      const double u = q.x() / q.z(), v = q.y() / q.z();
      const bool inside = q.z() > 0.0 && u >= 0.0 && v >= 0.0 && u <= size.width - 1.0 && v <= size.height - 1.0;
      tracked_points_[p] = inside ? cv::Point2f(static_cast<float>(u), static_cast<float>(v)) : points_[p];
    }
  }
  RunLucasKanade(previous, next, levels, cv::OPTFLOW_USE_INITIAL_FLOW);
}

LineRefit RefitTrackedLine(const TrackingOptions& options, const Segment2d& old, int sampled,
                           const std::vector<Eigen::Vector2d>& points, const std::vector<double>& positions,
                           Ransac<Eigen::Vector3d>* ransac, RansacResult<Eigen::Vector3d>* workspace) {
  LineRefit fit;
  const int needed = std::max(3, static_cast<int>(std::ceil(options.min_inlier_fraction * sampled)));
  if (static_cast<int>(points.size()) < needed) return fit;
  fit.loss = LineLoss::kRefit;
  LineEstimator estimator;
  estimator.points = &points;
  estimator.threshold_sq = options.inlier_px * options.inlier_px;
  RansacResult<Eigen::Vector3d>& result = *workspace;
  ransac->Run(estimator, RansacOptions{50, 0.999}, {}, &result);
  if (!result.success || static_cast<int>(result.inliers.size()) < needed) return fit;
  fit.inliers = static_cast<int>(result.inliers.size());
  const Eigen::Vector3d line = result.model;
  double sq = 0.0;
  for (int i : result.inliers) {
    const double r = line.head<2>().dot(points[i]) + line.z();
    sq += r * r;
  }
  fit.rms_px = std::sqrt(sq / result.inliers.size());
  if (fit.rms_px > options.max_rms_px) return fit;
  // Direction along the old segment's orientation, and a point on the new line.
  const Eigen::Vector2d a = old.head<2>();
  const double length = (old.tail<2>() - a).norm();
  Eigen::Vector2d dir(line.y(), -line.x());
  if (dir.dot(old.tail<2>() - a) < 0) dir = -dir;
  const Eigen::Vector2d base = -line.z() * line.head<2>();
  // t' = alpha t + beta by least squares over the inliers.
  double st = 0, stt = 0, su = 0, stu = 0;
  for (int i : result.inliers) {
    const double t = positions[i], u = dir.dot(points[i] - base);
    st += t;
    stt += t * t;
    su += u;
    stu += t * u;
  }
  const double m = static_cast<double>(result.inliers.size());
  const double det = m * stt - st * st;
  if (det <= 1e-9) return fit;
  const double alpha = (m * stu - st * su) / det, beta = (su - alpha * st) / m;
  if (!(alpha > 0.5 && alpha < 2.0)) return fit;
  const Eigen::Vector2d p = base + beta * dir, q = base + (alpha * length + beta) * dir;
  fit.segment = Segment2d(p.x(), p.y(), q.x(), q.y());
  fit.loss = LineLoss::kKept;
  return fit;
}

const char* LineLossName(LineLoss loss) {
  switch (loss) {
    case LineLoss::kKept: return "kept";
    case LineLoss::kFlowAtBorder: return "flow_at_border";
    case LineLoss::kFlowPoints: return "flow_points";
    case LineLoss::kRefit: return "refit";
    case LineLoss::kSnap: return "snap";
    case LineLoss::kDirection: return "direction";
    case LineLoss::kShort: return "short";
    case LineLoss::kStereo: return "stereo";
  }
  return "unknown";
}

void LineFlowTracker::Refit(int width, int height, std::vector<Segment2d>* tracked, std::vector<LineLoss>* losses) {
  const int n = static_cast<int>(segments_.size());
  tracked->assign(n, Segment2d::Zero());
  losses->assign(n, LineLoss::kKept);
  // A segment whose flow points come within the LK window of the border is leaving the view.
  const double border = options_.window_px;
  const auto near_border = [&](const cv::Point2f& q) {
    return q.x < border || q.y < border || q.x > width - 1 - border || q.y > height - 1 - border;
  };
  double rms_sum = 0.0;
  int kept = 0;
  for (int s = 0; s < n; ++s) {
    const Segment2d& old = segments_[s];
    const double length = (old.tail<2>() - old.head<2>()).norm();
    const int k = first_point_[s + 1] - first_point_[s];
    data_.clear();
    positions_.clear();
    for (int i = 0; i < k; ++i) {
      const int p = first_point_[s] + i;
      if (!status_[p] || !std::isfinite(tracked_points_[p].x) || !std::isfinite(tracked_points_[p].y)) continue;
      data_.emplace_back(tracked_points_[p].x, tracked_points_[p].y);
      positions_.push_back(length * i / (k - 1));
    }
    LineRefit fit = RefitTrackedLine(options_, old, k, data_, positions_, &ransac_, &result_);
    LineLoss& loss = (*losses)[s];
    if (!fit.ok()) {
      loss = fit.loss;
      if (loss == LineLoss::kFlowPoints &&
          std::any_of(points_.begin() + first_point_[s], points_.begin() + first_point_[s + 1], near_border)) {
        loss = LineLoss::kFlowAtBorder;
      }
      continue;
    }
    if (options_.snap_radius_px > 0.0) {
      double direction_sigma_deg = 0.0;
      if (!SnapSegmentToEdges(options_, derivatives_, &fit.segment, &snap_, &direction_sigma_deg)) {
        loss = LineLoss::kSnap;
        continue;
      }
      if (DirectionUndetermined(options_, direction_sigma_deg)) {
        loss = LineLoss::kDirection;
        continue;
      }
      // The snap only trims; the extent grows back along the edge here (tracked lines only).
      ExtendAlongEdge(options_, derivatives_, &fit.segment);
    }
    if (!ClipSegmentToImage(width, height, &fit.segment) ||
        (fit.segment.tail<2>() - fit.segment.head<2>()).norm() < options_.min_length_px) {
      loss = LineLoss::kShort;
      continue;
    }
    (*tracked)[s] = fit.segment;
    rms_sum += fit.rms_px;
    ++kept;
  }
  last_mean_rms_ = kept > 0 ? rms_sum / kept : 0.0;
}

}  // namespace slt
