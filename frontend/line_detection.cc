#include "frontend/line_detection.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <opencv2/line_descriptor.hpp>
#include <opencv2/ximgproc/edge_drawing.hpp>
#include <opencv2/ximgproc/fast_line_detector.hpp>
#include <stdexcept>

#include "frontend/image_sampling.h"

namespace slt {
namespace {

Segment2d ToSegment(const cv::Vec4f& v) { return Segment2d(v[0], v[1], v[2], v[3]); }

class LsdDetector : public LineDetector {
 public:
  // Every parameter from DetectionOptions (lsd_*; the gradient quantisation bound `quant` sets
  // the smallest gradient magnitude LSD considers); OpenCV's 1024 bins of its pseudo-ordering.
  explicit LsdDetector(const DetectionOptions& options)
      : lsd_(cv::createLineSegmentDetector(options.lsd_refine ? cv::LSD_REFINE_STD : cv::LSD_REFINE_NONE,
                                           options.lsd_scale, options.lsd_sigma_scale, options.lsd_quant,
                                           options.lsd_angle_deg, /*log_eps=*/0.0, options.lsd_density)) {}
  void Detect(const cv::Mat& grey, std::vector<Segment2d>* segments) override {
    lines_.clear();
    lsd_->detect(grey, lines_);
    segments->clear();
    for (const cv::Vec4f& v : lines_) segments->push_back(ToSegment(v));
  }

 private:
  cv::Ptr<cv::LineSegmentDetector> lsd_;
  std::vector<cv::Vec4f> lines_;
};

class EdlinesDetector : public LineDetector {
 public:
  explicit EdlinesDetector(const DetectionOptions& options) : ed_(cv::ximgproc::createEdgeDrawing()) {
    ed_->params.GradientThresholdValue = options.edlines_gradient_threshold;
  }
  void Detect(const cv::Mat& grey, std::vector<Segment2d>* segments) override {
    lines_.clear();
    ed_->detectEdges(grey);
    ed_->detectLines(lines_);
    segments->clear();
    for (const cv::Vec4f& v : lines_) segments->push_back(ToSegment(v));
  }

 private:
  cv::Ptr<cv::ximgproc::EdgeDrawing> ed_;
  std::vector<cv::Vec4f> lines_;
};

class FldDetector : public LineDetector {
 public:
  // OpenCV's defaults: length 10 px, 1.41 px from the fitted line, Canny 50/50, aperture 3.
  FldDetector() : fld_(cv::ximgproc::createFastLineDetector()) {}
  void Detect(const cv::Mat& grey, std::vector<Segment2d>* segments) override {
    lines_.clear();
    fld_->detect(grey, lines_);
    segments->clear();
    for (const cv::Vec4f& v : lines_) segments->push_back(ToSegment(v));
  }

 private:
  cv::Ptr<cv::ximgproc::FastLineDetector> fld_;
  std::vector<cv::Vec4f> lines_;
};

class BinaryDescriptorDetector : public LineDetector {
 public:
  BinaryDescriptorDetector() : bd_(cv::line_descriptor::BinaryDescriptor::createBinaryDescriptor()) {}
  void Detect(const cv::Mat& grey, std::vector<Segment2d>* segments) override {
    keylines_.clear();
    bd_->detect(grey, keylines_);
    segments->clear();
    // The finest octave only: coarser octaves repeat the same lines, less precisely.
    for (const cv::line_descriptor::KeyLine& k : keylines_) {
      if (k.octave == 0) segments->emplace_back(k.startPointX, k.startPointY, k.endPointX, k.endPointY);
    }
  }

 private:
  cv::Ptr<cv::line_descriptor::BinaryDescriptor> bd_;
  std::vector<cv::line_descriptor::KeyLine> keylines_;
};

// Paper Sec. 3.1: Canny edges; straight runs found by the probabilistic Hough transform, then
// each refitted (total least squares) to the edge pixels within 1.5 px of it, which removes
// the Hough quantisation.
class CannyHoughDetector : public LineDetector {
 public:
  void Detect(const cv::Mat& grey, std::vector<Segment2d>* segments) override {
    cv::GaussianBlur(grey, blurred_, cv::Size(5, 5), 1.0);
    cv::Canny(blurred_, edges_, 20, 60, 3, true);
    lines_.clear();
    cv::HoughLinesP(edges_, lines_, 1.0, CV_PI / 360.0, 20, 15.0, 2.0);
    segments->clear();
    for (const cv::Vec4i& l : lines_) {
      const Eigen::Vector2d a(l[0], l[1]), b(l[2], l[3]);
      const double length = (b - a).norm();
      if (length < 1.0) continue;
      const Eigen::Vector2d d = (b - a) / length, n(-d.y(), d.x());
      // Edge pixels near the segment: scan a thin band along it.
      Eigen::Vector2d sum = Eigen::Vector2d::Zero();
      Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
      int count = 0;
      for (double t = 0.0; t <= length; t += 1.0) {
        for (int off = -1; off <= 1; ++off) {
          const Eigen::Vector2d p = a + t * d + off * n;
          const int u = static_cast<int>(std::lround(p.x())), v = static_cast<int>(std::lround(p.y()));
          if (u < 0 || v < 0 || u >= edges_.cols || v >= edges_.rows || !edges_.at<uchar>(v, u)) continue;
          const Eigen::Vector2d q(u, v);
          if (std::abs(n.dot(q - a)) > 1.5) continue;
          sum += q;
          scatter += q * q.transpose();
          ++count;
        }
      }
      if (count < 5) {
        segments->emplace_back(a.x(), a.y(), b.x(), b.y());
        continue;
      }
      const Eigen::Vector2d mean = sum / count;
      const Eigen::Matrix2d cov = scatter / count - mean * mean.transpose();
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
      Eigen::Vector2d dir = eig.eigenvectors().col(1);
      if (dir.dot(d) < 0) dir = -dir;
      const Eigen::Vector2d p = mean + dir * dir.dot(a - mean), q = mean + dir * dir.dot(b - mean);
      segments->emplace_back(p.x(), p.y(), q.x(), q.y());
    }
  }

 private:
  cv::Mat blurred_, edges_;
  std::vector<cv::Vec4i> lines_;
};

}  // namespace

std::unique_ptr<LineDetector> MakeLineDetector(const DetectionOptions& options) {
  switch (options.detector) {
    case LineDetectorType::kLsd: return std::make_unique<LsdDetector>(options);
    case LineDetectorType::kEdlines: return std::make_unique<EdlinesDetector>(options);
    case LineDetectorType::kFld: return std::make_unique<FldDetector>();
    case LineDetectorType::kBinaryDescriptor: return std::make_unique<BinaryDescriptorDetector>();
    case LineDetectorType::kCannyHough: return std::make_unique<CannyHoughDetector>();
  }
  throw std::invalid_argument("unknown line detector");
}

void MergeCollinearSegments(const DetectionOptions& options, std::vector<Segment2d>* segments, bool oriented) {
  const double max_angle = options.merge_angle_deg * M_PI / 180.0;
  // Directions as angles in [0, period): modulo pi for undirected segments, 2 pi for oriented
  // ones (opposite polarity: opposite directions, more than max_angle apart).
  const double period = oriented ? 2.0 * M_PI : M_PI;
  std::vector<double> angle;
  std::vector<int> order;
  std::vector<char> gone;
  for (bool merged = true; merged;) {
    merged = false;
    const int n = static_cast<int>(segments->size());
    angle.resize(n);
    for (int i = 0; i < n; ++i) {
      const Segment2d& s = (*segments)[i];
      double a = std::atan2(s[3] - s[1], s[2] - s[0]);
      if (a < 0) a += period;
      if (a >= period) a -= period;
      angle[i] = a;
    }
    order.resize(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int x, int y) { return angle[x] < angle[y]; });
    gone.assign(n, 0);
    // Pairs within max_angle are neighbours in the sorted order (with wrap-around at period).
    for (int oi = 0; oi < n; ++oi) {
      const int i = order[oi];
      if (gone[i]) continue;
      for (int step = 1; step < n; ++step) {
        const int j = order[(oi + step) % n];
        double diff = angle[j] - angle[i];
        if (oi + step >= n) diff += period;
        if (diff > max_angle) break;
        if (gone[j]) continue;
        Segment2d& si = (*segments)[i];
        const Segment2d& sj = (*segments)[j];
        const bool i_longer = (si.tail<2>() - si.head<2>()).squaredNorm() >= (sj.tail<2>() - sj.head<2>()).squaredNorm();
        const Segment2d& l = i_longer ? si : sj;
        const Segment2d& s = i_longer ? sj : si;
        const Eigen::Vector2d a = l.head<2>();
        const double length = (l.tail<2>() - a).norm();
        if (length < 1e-9) continue;
        const Eigen::Vector2d d = (l.tail<2>() - a) / length, nrm(-d.y(), d.x());
        if (std::abs(nrm.dot(s.head<2>() - a)) > options.merge_distance_px ||
            std::abs(nrm.dot(s.tail<2>() - a)) > options.merge_distance_px) {
          continue;
        }
        const double t0 = d.dot(s.head<2>() - a), t1 = d.dot(s.tail<2>() - a);
        const double gap = std::max(std::min(t0, t1) - length, -std::max(t0, t1));
        if (gap > options.merge_gap_px) continue;
        const double lo = std::min({0.0, t0, t1}), hi = std::max({length, t0, t1});
        const Eigen::Vector2d p = a + lo * d, q = a + hi * d;
        si = Segment2d(p.x(), p.y(), q.x(), q.y());
        angle[i] = angle[i_longer ? i : j];
        gone[j] = 1;
        merged = true;
      }
    }
    if (merged) {
      int k = 0;
      for (int i = 0; i < n; ++i) {
        if (!gone[i]) (*segments)[k++] = (*segments)[i];
      }
      segments->resize(k);
    }
  }
}

float OrientByGradient(const cv::Mat& grey, Segment2d* segment) {
  const Eigen::Vector2d a = segment->head<2>(), b = segment->tail<2>();
  const double length = (b - a).norm();
  if (length < 1e-9) return 0.0f;
  const Eigen::Vector2d d = (b - a) / length, n(-d.y(), d.x());
  const int samples = std::max(2, static_cast<int>(length / 2.0));
  double sum = 0.0;
  for (int i = 0; i < samples; ++i) {
    const Eigen::Vector2d p = a + (i + 0.5) * (length / samples) * d;
    const Eigen::Vector2d plus = p + 2.0 * n, minus = p - 2.0 * n;
    sum += SampleBilinear<uchar>(grey, plus.x(), plus.y()) - SampleBilinear<uchar>(grey, minus.x(), minus.y());
  }
  const double mean = sum / samples;
  if (mean < 0) *segment = Segment2d(b.x(), b.y(), a.x(), a.y());
  return static_cast<float>(std::abs(mean));
}

bool ClipSegmentToImage(int width, int height, Segment2d* segment) {
  // Liang-Barsky against [0, w-1] x [0, h-1].
  const Eigen::Vector2d a = segment->head<2>(), d = segment->tail<2>() - a;
  double t0 = 0.0, t1 = 1.0;
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {a.x(), width - 1.0 - a.x(), a.y(), height - 1.0 - a.y()};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
      continue;
    }
    const double r = q[i] / p[i];
    if (p[i] < 0.0) t0 = std::max(t0, r);
    else t1 = std::min(t1, r);
  }
  if (t0 > t1) return false;
  const Eigen::Vector2d p0 = a + t0 * d, p1 = a + t1 * d;
  *segment = Segment2d(p0.x(), p0.y(), p1.x(), p1.y());
  return true;
}

bool LiesAlong(const Segment2d& line, const Segment2d& segment, double cos_max_angle, double max_distance_px) {
  const Eigen::Vector2d p = line.head<2>(), d = (line.tail<2>() - p).normalized(), n(-d.y(), d.x());
  const Eigen::Vector2d e = (segment.tail<2>() - segment.head<2>()).normalized();
  return std::abs(d.dot(e)) >= cos_max_angle && std::abs(n.dot(segment.head<2>() - p)) <= max_distance_px &&
         std::abs(n.dot(segment.tail<2>() - p)) <= max_distance_px;
}

std::vector<ImageLine> DetectLines(LineDetector& detector, const DetectionOptions& options, const cv::Mat& grey) {
  if (grey.type() != CV_8UC1) throw std::invalid_argument("DetectLines: expected an 8-bit grey image");
  std::vector<Segment2d> segments;
  // Detectors read the pixels as one block (LSD, EdgeDrawing): a view into a larger image (the
  // flow pyramid's level 0, which the front end detects on for the measured-motion check) is
  // copied first.
  detector.Detect(grey.isContinuous() ? grey : grey.clone(), &segments);
  if (options.merge_same_polarity) {
    // Each fragment oriented by its own gradient first, so that only fragments with the same
    // brighter side merge: an edge whose brighter side changes along it (a shelf's front
    // edge under books lighter and darker than the shelf) stays apart in pieces of one
    // polarity instead of one segment whose contrast averages out.
    for (Segment2d& s : segments) OrientByGradient(grey, &s);
  }
  MergeCollinearSegments(options, &segments, options.merge_same_polarity);
  std::vector<ImageLine> lines;
  lines.reserve(segments.size());
  const double min_sq = options.min_length_px * options.min_length_px;
  for (Segment2d& s : segments) {
    if (!ClipSegmentToImage(grey.cols, grey.rows, &s)) continue;
    if ((s.tail<2>() - s.head<2>()).squaredNorm() < min_sq) continue;
    ImageLine line;
    line.segment = s;
    line.contrast = OrientByGradient(grey, &line.segment);
    if (line.contrast < options.min_contrast) continue;
    lines.push_back(line);
  }
  return lines;
}

}  // namespace slt
