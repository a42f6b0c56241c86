// In-memory stereo line observations: what the `stereo-lines/1` format holds
// (docs/formats.md), what the simulator produces and what every tracker consumes.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/camera.h"
#include "geometry/line2d.h"

namespace slt {

// One observed line segment, in pixels. The same `id` in the left and right images of a frame
// is one 3-D line (a stereo match); the same `id` over frames is one tracked line.
struct LineObservation {
  std::int64_t id = 0;
  Segment2d segment = Segment2d::Zero();  // [u1 v1 u2 v2]
};

struct StereoFrame {
  double time = 0.0;  // seconds
  std::vector<LineObservation> left;
  std::vector<LineObservation> right;
};

struct StereoSequence {
  StereoRig rig;
  std::vector<StereoFrame> frames;
};

// The sequence with only the observations whose id `keep(id)` accepts (rig and times kept).
template <typename Keep>
StereoSequence FilterLines(const StereoSequence& sequence, Keep keep) {
  StereoSequence out;
  out.rig = sequence.rig;
  for (const StereoFrame& frame : sequence.frames) {
    StereoFrame& f = out.frames.emplace_back();
    f.time = frame.time;
    for (const LineObservation& o : frame.left) {
      if (keep(o.id)) f.left.push_back(o);
    }
    for (const LineObservation& o : frame.right) {
      if (keep(o.id)) f.right.push_back(o);
    }
  }
  return out;
}

}  // namespace slt
