#include "frontend/parallel_edges.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "frontend/image_sampling.h"

namespace slt {
namespace {

constexpr double kStepPx = 0.5;          // profile sampling across the line
constexpr double kMinOffsetPx = 1.5;     // closer edges are not resolved by the blur and the snap
constexpr double kPlaceSpacingPx = 3.0;  // profile places along the line ...
constexpr int kMaxPlaces = 16;           // ... at most this many
constexpr double kEndMarginPx = 3.0;     // places keep off the ends (corners)
constexpr int kMaxHalfWidth = 2 * 10 + 4;  // offsets of the widest profile (parallel_edge_px <= 10), in steps

// Undirected angle of a segment in [0, pi).
double UndirectedAngle(const Segment2d& s) {
  double a = std::atan2(s[3] - s[1], s[2] - s[0]);
  if (a < 0.0) a += M_PI;
  return a >= M_PI ? a - M_PI : a;
}

// The detections sorted by undirected angle, to find those within an angle of a line.
class AngleIndex {
 public:
  explicit AngleIndex(const std::vector<ImageLine>& lines) {
    entries_.reserve(lines.size());
    for (size_t i = 0; i < lines.size(); ++i) entries_.push_back({UndirectedAngle(lines[i].segment), static_cast<int>(i)});
    std::sort(entries_.begin(), entries_.end());
  }
  // Calls f(i) for every line within max_angle (rad, < pi / 2) of `angle`, modulo pi.
  template <typename F>
  bool Any(double angle, double max_angle, F&& f) const {
    for (const double shift : {0.0, M_PI, -M_PI}) {  // the window wraps around 0 and pi
      const double lo = angle + shift - max_angle, hi = angle + shift + max_angle;
      if (hi < 0.0 || lo >= M_PI) continue;
      auto it = std::lower_bound(entries_.begin(), entries_.end(), std::make_pair(lo, -1));
      for (; it != entries_.end() && it->first <= hi; ++it) {
        if (f(it->second)) return true;
      }
    }
    return false;
  }

 private:
  std::vector<std::pair<double, int>> entries_;
};

}  // namespace

void AddParallelEdges(const DetectionOptions& options, double min_gradient, const cv::Mat& grey,
                      std::vector<ImageLine>* lines) {
  if (options.parallel_edge_px <= 0.0) return;
  const double max_angle = options.merge_angle_deg * M_PI / 180.0, cos_max = std::cos(max_angle);
  const double min_sq = options.min_length_px * options.min_length_px;
  // Offsets in steps of kStepPx: candidates at first_step .. last_step, the profile two
  // pixels wider for the minima around them.
  const int first_step = static_cast<int>(std::ceil(kMinOffsetPx / kStepPx));
  const int last_step = static_cast<int>(std::floor(std::min(options.parallel_edge_px, 10.0) / kStepPx));
  if (last_step < first_step) return;
  const int half = last_step + static_cast<int>(2.0 / kStepPx), width = 2 * half + 1;
  // Per place m the profile P_m(k kStepPx) at places[m * width + k + half]; the mean over the
  // places (0) and over each half of them (1, 2), and their derivatives G.
  std::vector<float> places_profile(static_cast<size_t>(kMaxPlaces) * width);
  std::array<std::array<float, 2 * kMaxHalfWidth + 1>, 3> profiles{}, gradients{};
  const AngleIndex index(*lines);
  const size_t detected = lines->size();
  // A new line and the lines along it (within merge_angle_deg and merge_distance_px): when one
  // of them at least as long covers half of either, the new line is known; shorter ones it
  // covers half of (an edge the detector found only in part) are replaced by it.
  std::vector<char> replaced(detected, 0);
  std::vector<int> covered;
  const auto overlap = [](const Segment2d& s, const Segment2d& t) {
    const Eigen::Vector2d p = s.head<2>(), d = (s.tail<2>() - p).normalized();
    const double t0 = d.dot(t.head<2>() - p), t1 = d.dot(t.tail<2>() - p);
    return std::min((s.tail<2>() - p).norm(), std::max(t0, t1)) - std::max(0.0, std::min(t0, t1));
  };
  const auto is_known = [&](const Segment2d& segment) {
    covered.clear();
    const double length = (segment.tail<2>() - segment.head<2>()).norm();
    const auto along = [&](int i) {
      const Segment2d& other = (*lines)[i].segment;
      if (!LiesAlong(other, segment, cos_max, options.merge_distance_px)) return false;
      const double other_length = (other.tail<2>() - other.head<2>()).norm();
      if (overlap(segment, other) < 0.5 * std::min(length, other_length)) return false;
      if (other_length >= length) return true;
      covered.push_back(i);
      return false;
    };
    if (index.Any(UndirectedAngle(segment), max_angle, along)) return true;
    for (size_t i = detected; i < lines->size(); ++i) {  // the lines added so far
      if (along(static_cast<int>(i))) return true;
    }
    return false;
  };
  const float max_u = static_cast<float>(grey.cols - 1), max_v = static_cast<float>(grey.rows - 1);
  for (size_t i = 0; i < detected; ++i) {
    const Segment2d source = (*lines)[i].segment;
    const Eigen::Vector2d a = source.head<2>(), b = source.tail<2>();
    const double length = (b - a).norm();
    if (length * length < min_sq) continue;
    const Eigen::Vector2d d = (b - a) / length, n(-d.y(), d.x());
    const double margin = std::min(kEndMarginPx, 0.25 * length), span = length - 2.0 * margin;
    const int places = std::clamp(static_cast<int>(span / kPlaceSpacingPx), 4, kMaxPlaces);
    const auto along = [&](double m) { return margin + (m + 0.5) * span / places; };  // place m's distance from a
    const float nu = static_cast<float>(kStepPx * n.x()), nv = static_cast<float>(kStepPx * n.y());
    for (auto& p : profiles) std::fill(p.begin(), p.end(), 0.0f);
    for (int m = 0; m < places; ++m) {
      const Eigen::Vector2d x = a + along(m) * d;
      const float u0 = static_cast<float>(x.x()), v0 = static_cast<float>(x.y());
      float* pm = &places_profile[static_cast<size_t>(m) * width + half];
      float* ph = profiles[m < places / 2 ? 1 : 2].data() + kMaxHalfWidth;
      const float u_first = u0 - half * nu, v_first = v0 - half * nv;
      const float u_last = u0 + half * nu, v_last = v0 + half * nv;
      if (std::min(u_first, u_last) >= 0.0f && std::min(v_first, v_last) >= 0.0f && std::max(u_first, u_last) < max_u &&
          std::max(v_first, v_last) < max_v) {
        // Inside: bilinear without clamping, the common case.
        for (int k = -half; k <= half; ++k) {
          const float u = u0 + k * nu, v = v0 + k * nv;
          const int iu = static_cast<int>(u), iv = static_cast<int>(v);
          const float fu = u - iu, fv = v - iv;
          const uchar* r0 = grey.ptr<uchar>(iv) + iu;
          const uchar* r1 = r0 + grey.step[0];
          pm[k] = (1.0f - fv) * ((1.0f - fu) * r0[0] + fu * r0[1]) + fv * ((1.0f - fu) * r1[0] + fu * r1[1]);
        }
      } else {
        // Off the image: the border value (SampleBilinear clamps), no edge there.
        for (int k = -half; k <= half; ++k) pm[k] = SampleBilinear<uchar>(grey, u0 + k * nu, v0 + k * nv);
      }
      for (int k = -half; k <= half; ++k) ph[k] += pm[k];
    }
    const int in_half[3] = {places, places / 2, places - places / 2};
    for (int h = 0; h < 3; ++h) {
      float* p = profiles[h].data() + kMaxHalfWidth;
      if (h == 0) {
        for (int k = -half; k <= half; ++k) p[k] = profiles[1][k + kMaxHalfWidth] + profiles[2][k + kMaxHalfWidth];
      }
      for (int k = -half; k <= half; ++k) p[k] /= in_half[h];
      float* g = gradients[h].data() + kMaxHalfWidth;
      for (int k = -half + 1; k < half; ++k) g[k] = static_cast<float>((p[k + 1] - p[k - 1]) / (2.0 * kStepPx));
    }
    const float* profile = profiles[0].data() + kMaxHalfWidth;
    const float* gradient = gradients[0].data() + kMaxHalfWidth;
    for (int k = -last_step; k <= last_step; ++k) {
      if (std::abs(k) < first_step) continue;
      const float g = gradient[k], sign = g >= 0.0f ? 1.0f : -1.0f;
      if (sign * g < min_gradient || sign * g < sign * gradient[k - 1] || sign * g < sign * gradient[k + 1]) continue;
      // The step of this edge alone: between the minima of sign * G on either side.
      int lo = k, hi = k;
      while (lo - 1 > -half && sign * gradient[lo - 1] < sign * gradient[lo] && sign * gradient[lo - 1] > 0.0f) --lo;
      while (hi + 1 < half && sign * gradient[hi + 1] < sign * gradient[hi] && sign * gradient[hi + 1] > 0.0f) ++hi;
      const float step = sign * (profile[hi + 1] - profile[lo - 1]);
      if (step < options.min_contrast) continue;
      // The edge's offset in each half of the places (a peak within a step of k, at least half
      // the mean's, sub-sample by a parabola): the line through the two, which need not be
      // exactly parallel to the source.
      Eigen::Vector2d offset_at;  // at the two halves' mean places
      bool both = true;
      for (int h = 1; h <= 2 && both; ++h) {
        const float* gh = gradients[h].data() + kMaxHalfWidth;
        int best = k;
        for (int j = k - 1; j <= k + 1; ++j) {
          if (sign * gh[j] > sign * gh[best]) best = j;
        }
        const float gm = sign * gh[best - 1], g0 = sign * gh[best], gp = sign * gh[best + 1];
        if (g0 < 0.5f * sign * g || gm > g0 || gp > g0) {
          both = false;
          break;
        }
        const float curvature = gm - 2.0f * g0 + gp;
        const double delta = curvature < 0.0f ? std::clamp(0.5f * (gm - gp) / curvature, -0.5f, 0.5f) : 0.0f;
        offset_at[h - 1] = (best + delta) * kStepPx;
      }
      if (!both) continue;
      const double t1 = along(0.5 * (places / 2) - 0.5), t2 = along(places / 2 + 0.5 * (places - places / 2) - 0.5);
      const auto offset = [&](double t) { return offset_at[0] + (offset_at[1] - offset_at[0]) * (t - t1) / (t2 - t1); };
      // Trimmed to the places whose own profile has the edge (at least half the mean peak there).
      const auto on_edge = [&](int m) {
        const int j = std::clamp(static_cast<int>(std::lround(offset(along(m)) / kStepPx)), -half + 1, half - 1);
        const float* pm = &places_profile[static_cast<size_t>(m) * width + half];
        return sign * (pm[j + 1] - pm[j - 1]) / (2.0 * kStepPx) >= 0.5 * sign * g;
      };
      int first = 0, last = places - 1;
      while (first < last && !on_edge(first)) ++first;
      while (last > first && !on_edge(last)) --last;
      const double slack = 0.5 * span / places;
      const double t_start = first == 0 ? 0.0 : along(first) - slack, t_end = last == places - 1 ? length : along(last) + slack;
      if ((t_end - t_start) * (t_end - t_start) < min_sq) continue;
      const Eigen::Vector2d p = a + t_start * d + offset(t_start) * n, q = a + t_end * d + offset(t_end) * n;
      ImageLine line;
      // Oriented by its gradient: brighter at +n of the new segment.
      line.segment = sign > 0.0f ? Segment2d(p.x(), p.y(), q.x(), q.y()) : Segment2d(q.x(), q.y(), p.x(), p.y());
      if (!LiesAlong(source, line.segment, cos_max, std::numeric_limits<double>::infinity())) continue;
      if (is_known(line.segment)) continue;
      line.contrast = step;
      for (const int c : covered) {
        if (c < static_cast<int>(detected)) replaced[c] = 1;
      }
      lines->push_back(line);
    }
  }
  size_t kept = 0;
  for (size_t i = 0; i < lines->size(); ++i) {
    if (i >= detected || !replaced[i]) (*lines)[kept++] = (*lines)[i];
  }
  lines->resize(kept);
}

}  // namespace slt
