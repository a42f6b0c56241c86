// Line segment detection in one grey image (paper Sec. 3.1): a detector of OpenCV 4.6 or the
// paper's Canny-based path, then collinear fragments merged, short segments dropped and every
// segment oriented by the sign of the intensity gradient across it.
//
// Orientation: a segment s = [a; b] has direction d = (b - a) / |b - a| and normal
// n = (-d_v, d_u); it is oriented so that the image is brighter on the +n side:
//   I(x + 2n) > I(x - 2n) on average along the segment,
// so that corresponding segments in the two images of a pair (and over frames) point the same
// way, as the paper orients them before matching.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "frontend/frontend_options.h"
#include "geometry/line2d.h"

namespace slt {

struct ImageLine {
  Segment2d segment = Segment2d::Zero();  // oriented: brighter side at +n
  float contrast = 0.0f;                  // mean I(x + 2n) - I(x - 2n) along it, grey levels (> 0)
  double Length() const { return (segment.tail<2>() - segment.head<2>()).norm(); }
};

// One detector, set up once and applied to many images (8-bit grey, CV_8UC1).
class LineDetector {
 public:
  virtual ~LineDetector() = default;
  // The detector's raw segments (unoriented, unmerged, any length).
  virtual void Detect(const cv::Mat& grey, std::vector<Segment2d>* segments) = 0;
};
// The detector options.detector names, with its parameters from `options` (LSD's quant).
std::unique_ptr<LineDetector> MakeLineDetector(const DetectionOptions& options);

// Merges collinear fragments (options.merge_*) in place: the merged segment spans the extreme
// projections of both onto the longer one's line. Repeats until nothing merges. `oriented`:
// the segments are oriented (OrientByGradient) and only those pointing the same way merge
// (the same brighter side); else directions are compared modulo 180 deg.
void MergeCollinearSegments(const DetectionOptions& options, std::vector<Segment2d>* segments, bool oriented = false);

// Orients the segment (swapping its endpoints when needed) and returns its contrast (>= 0),
// sampled every 2 px along it.
float OrientByGradient(const cv::Mat& grey, Segment2d* segment);

// Detect, (orient and) merge, drop short and low-contrast segments, orient: what the front end
// matches. With options.merge_same_polarity the detector's fragments are oriented before the
// merge and only fragments of the same polarity merge.
std::vector<ImageLine> DetectLines(LineDetector& detector, const DetectionOptions& options, const cv::Mat& grey);

// Clips a segment to [0, width-1] x [0, height-1]; false when nothing is inside.
bool ClipSegmentToImage(int width, int height, Segment2d* segment);

// Whether `segment` lies along the line through `line`: |cos| of the angle between their
// directions at least cos_max_angle (either way round) and both of its endpoints within
// max_distance_px of that line. Its extent along the line is not compared.
bool LiesAlong(const Segment2d& line, const Segment2d& segment, double cos_max_angle, double max_distance_px);

}  // namespace slt
