// Second edges beside detected ones (docs/frontend.md, "Which segments are missed"): a thin
// board seen from 3 m (2 cm: 3 px at 458 px focal length) shows two parallel edges 2-4 px
// apart, often one strong and one weak (a shelf's lit top face and its front face differ by a
// few grey levels). A detector working on a smoothed, resampled image (LSD at scale 0.6) finds
// one line, which the snap (line_tracking.h) places on the stronger edge; the other is lost.
// The snap itself cannot find it: its Scharr derivative (a 2-px difference) merges two edges
// 2-3 px apart into one peak.
//
// For every detection s (unit direction d, normal n, length L) the intensity profile across it
// is sampled at places x_m every 3 px along it (at most 16, 3 px clear of its ends),
//   P_m(o) = I(x_m + o n),  o = -R-2 .. R+2 in steps of 0.5 px,  R = options.parallel_edge_px,
// averaged over all places (P) and over each half of them (P1, P2), and differentiated,
// G(o) = (P(o + 0.5) - P(o - 0.5)) / 1 px. Averaging along the line lowers the noise by the
// square root of the number of places, so a step of a few grey levels stands out. A second
// edge is a local extremum of G at 1.5 px <= |o| <= R, with
//   |G(o)| >= min_gradient (grey levels per px) and
//   its step s (P(o_hi) - P(o_lo)), between the minima of s G on either side of it
//   (s = sign G(o)), >= options.min_contrast: the edge alone, not its strong neighbour.
// Its offset is found in each half (the extremum of s G_h within 0.5 px of o, at least half of
// |G(o)|, sub-sample by a parabola), the line through the two (it need not be exactly parallel
// to s), trimmed to the places whose own profile has at least half that gradient there, and
// oriented by s (brighter side at +n). It is kept when
//   it is within options.merge_angle_deg of s and at least options.min_length_px long, and
//   it is a new edge: no line along it (within merge_angle_deg and options.merge_distance_px)
//   at least as long covers half of either; shorter ones it covers half of (an edge the
//   detector found in part) are replaced by it. The detections are indexed by angle, so the
//   search is O(N log N) in their number.
// Works on snapped and unsnapped detections alike.
#pragma once

#include <vector>

#include "frontend/frontend_options.h"
#include "frontend/line_detection.h"

namespace slt {

// Appends the second edges of `lines` found in `grey` up to options.parallel_edge_px beside
// them (nothing when that is 0); `min_gradient` in grey levels per px (the front end passes
// tracking.snap_min_gradient, the snap's weakest edge).
void AddParallelEdges(const DetectionOptions& options, double min_gradient, const cv::Mat& grey,
                      std::vector<ImageLine>* lines);

}  // namespace slt
