// Re-finding lost lines in the next frame by descriptor (large motion, issue 19): when the
// optical flow loses most live lines (a jump of tens of pixels on KITTI), each lost line is
// looked for among the lines detected in the new frame, by its MSLD descriptor (msld.h; Wang,
// Wu & Hu 2009, the descriptor the paper's stereo matching uses, Sec. 3.1), guided by where the
// predicted motion puts it (line_motion.h).
//
// A candidate c is admissible for a query q (its predicted segment p, its descriptor D_q) when
//   - its direction is within angle_deg of p's (oriented: both keep the brighter side at +n),
//   - both its endpoints lie within q's gate_px of p's line,
//   - it overlaps p along that line,
//   - |D_q - D_c| <= max_distance;
// a query keeps its nearest admissible candidate in descriptor distance when that is below
// ratio times the second nearest's. Pairs are then made one-to-one, nearest first.
#pragma once

#include <vector>

#include "frontend/msld.h"
#include "geometry/line2d.h"

namespace slt {

struct FrameMatchQuery {
  Segment2d predicted = Segment2d::Zero();
  MsldDescriptor descriptor;
  double gate_px = 10.0;
};

struct FrameMatchGates {
  double angle_deg = 5.0;
  double max_distance = 0.6;  // MSLD distance
  double ratio = 0.9;         // 1 = off
};

struct FrameMatch {
  int query = 0;
  int candidate = 0;
  float distance = 0.0f;
};

// The geometric part of the gate: `candidate` within angle_deg of `predicted`'s direction, both
// its endpoints within gate_px of its line, overlapping it along the line.
bool InsidePredictionGate(const Segment2d& predicted, const Segment2d& candidate, double angle_deg, double gate_px);

// Matches `queries` with the candidates (segments and their descriptors), one-to-one.
void MatchAcrossFrames(const FrameMatchGates& gates, const std::vector<FrameMatchQuery>& queries,
                       const std::vector<Segment2d>& candidates, const std::vector<MsldDescriptor>& descriptors,
                       std::vector<FrameMatch>* matches);

}  // namespace slt
