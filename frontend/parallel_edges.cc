#include "frontend/parallel_edges.h"

#include <cmath>
#include <limits>

namespace slt {

void AddParallelEdges(const DetectionOptions& options, const TrackingOptions& tracking, const cv::Mat& grey,
                      const cv::Mat& derivatives, std::vector<ImageLine>* lines, SnapWorkspace* workspace) {
  if (options.parallel_edge_px <= 0.0 || tracking.snap_radius_px <= 0.0) return;
  const double cos_max = std::cos(options.merge_angle_deg * M_PI / 180.0);
  const double min_sq = options.min_length_px * options.min_length_px;
  const size_t detected = lines->size();
  for (size_t i = 0; i < detected; ++i) {
    const Segment2d source = (*lines)[i].segment;
    const Eigen::Vector2d a = source.head<2>(), b = source.tail<2>();
    const double length = (b - a).norm();
    if (length < 1e-9) continue;
    const Eigen::Vector2d d = (b - a) / length, n(-d.y(), d.x());
    for (const double side : {-1.0, 1.0}) {
      const Eigen::Vector2d shift = side * options.parallel_edge_px * n;
      ImageLine line;
      line.segment << a + shift, b + shift;
      double direction_sigma_deg = 0.0;
      if (!SnapSegmentToEdges(tracking, derivatives, &line.segment, workspace, &direction_sigma_deg) ||
          DirectionUndetermined(tracking, direction_sigma_deg)) {
        continue;
      }
      if ((line.segment.tail<2>() - line.segment.head<2>()).squaredNorm() < min_sq) continue;
      if (!LiesAlong(source, line.segment, cos_max, std::numeric_limits<double>::infinity())) continue;
      bool known = false;
      for (const ImageLine& other : *lines) {
        if (LiesAlong(other.segment, line.segment, cos_max, options.merge_distance_px)) {
          known = true;
          break;
        }
      }
      if (known) continue;
      line.contrast = OrientByGradient(grey, &line.segment);
      if (line.contrast >= options.min_contrast) lines->push_back(line);
    }
  }
}

}  // namespace slt
