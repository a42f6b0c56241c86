// Second edges beside detected ones (docs/frontend.md, "Which ground-truth segments are
// missed"): a thin board seen from 3 m (2 cm: 3 px at 458 px focal length) shows two parallel
// edges 2-4 px apart. A detector working on a smoothed, resampled image (LSD at scale 0.6)
// finds one line between or on the stronger of them, and the snap (line_tracking.h) places it
// on that one; the other edge is not found.
//
// For every snapped detection s, with unit normal n, the segment s + o n for
// o = +-options.parallel_edge_px is snapped onto the edge there (SnapSegmentToEdges: the
// strongest gradient within the snap radius of the polarity found at its place). The result is
// a new line when it is
//   parallel to s (within options.merge_angle_deg),
//   a distinct edge: not within options.merge_distance_px (both endpoints) of any detection's
//   line nor of a line added before, at the same angle, and
//   long and contrasted enough (options.min_length_px, options.min_contrast; oriented by its
//   gradient as DetectLines orients).
#pragma once

#include <vector>

#include "frontend/frontend_options.h"
#include "frontend/line_detection.h"
#include "frontend/line_tracking.h"

namespace slt {

// Appends the second edges of `lines` (snapped detections) found in `grey` (its derivatives
// `derivatives`, as SnapSegmentToEdges takes them), with the shift options.parallel_edge_px;
// nothing when it is 0 or the snap is off.
void AddParallelEdges(const DetectionOptions& options, const TrackingOptions& tracking, const cv::Mat& grey,
                      const cv::Mat& derivatives, std::vector<ImageLine>* lines, SnapWorkspace* workspace);

}  // namespace slt
