#include "frontend/frame_matching.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slt {
namespace {

// Geometry of the gate: true when `c` lies near `p`'s line, along its direction, overlapping it.
bool InsideGate(const Segment2d& p, const Segment2d& c, double cos_angle, double gate_px) {
  const Eigen::Vector2d a = p.head<2>(), b = p.tail<2>();
  const double length = (b - a).norm();
  if (length < 1e-9) return false;
  const Eigen::Vector2d d = (b - a) / length, n(-d.y(), d.x());
  const Eigen::Vector2d ca = c.head<2>(), cb = c.tail<2>();
  const double c_length = (cb - ca).norm();
  if (c_length < 1e-9 || d.dot(cb - ca) < cos_angle * c_length) return false;
  if (std::abs(n.dot(ca - a)) > gate_px || std::abs(n.dot(cb - a)) > gate_px) return false;
  const double t0 = d.dot(ca - a), t1 = d.dot(cb - a);
  return std::max(t0, t1) > 0.0 && std::min(t0, t1) < length;
}

}  // namespace

bool InsidePredictionGate(const Segment2d& predicted, const Segment2d& candidate, double angle_deg, double gate_px) {
  return InsideGate(predicted, candidate, std::cos(angle_deg * M_PI / 180.0), gate_px);
}

void MatchAcrossFrames(const FrameMatchGates& gates, const std::vector<FrameMatchQuery>& queries,
                       const std::vector<Segment2d>& candidates, const std::vector<MsldDescriptor>& descriptors,
                       std::vector<FrameMatch>* matches) {
  matches->clear();
  const double cos_angle = std::cos(gates.angle_deg * M_PI / 180.0);
  for (int q = 0; q < static_cast<int>(queries.size()); ++q) {
    const FrameMatchQuery& query = queries[q];
    float best = std::numeric_limits<float>::infinity(), second = best;
    int best_index = -1;
    for (int c = 0; c < static_cast<int>(candidates.size()); ++c) {
      if (!InsideGate(query.predicted, candidates[c], cos_angle, query.gate_px)) continue;
      const float distance = (query.descriptor - descriptors[c]).norm();
      if (distance < best) {
        second = best;
        best = distance;
        best_index = c;
      } else if (distance < second) {
        second = distance;
      }
    }
    if (best_index < 0 || best > gates.max_distance) continue;
    if (std::isfinite(second) && best > gates.ratio * second) continue;
    matches->push_back({q, best_index, best});
  }
  std::sort(matches->begin(), matches->end(),
            [](const FrameMatch& x, const FrameMatch& y) { return x.distance < y.distance; });
  std::vector<char> taken(candidates.size(), 0);
  size_t kept = 0;
  for (const FrameMatch& m : *matches) {
    if (taken[m.candidate]) continue;
    taken[m.candidate] = 1;
    (*matches)[kept++] = m;
  }
  matches->resize(kept);
}

}  // namespace slt
