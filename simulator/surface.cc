#include "simulator/surface.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace slt {
namespace {

// Collinear edges closer than this (metres) are one line; the scenes place distinct parallel
// edges millimetres apart at least.
constexpr double kMergeTolerance = 1e-9;
// An occluder must be in front of the point by this fraction of the eye-point distance, and
// the crossing inside its polygon by this margin (metres): a segment on a polygon's edge or in
// its plane is not hidden by it.
constexpr double kDepthMargin = 1e-6;
constexpr double kInsideMargin = 1e-9;

struct MergedLine {
  Eigen::Vector3d p, q;  // the extreme points along the direction
  Eigen::Vector3d direction;
};

// The interval of `edge` along `line` when it is on the line, else false.
bool OnLine(const MergedLine& line, const Eigen::Vector3d& x, double* along) {
  const Eigen::Vector3d d = x - line.p;
  *along = d.dot(line.direction);
  return (d - *along * line.direction).norm() <= kMergeTolerance;
}

// Merges segment [x, y] into `line` when collinear and overlapping or touching.
bool TryMerge(MergedLine* line, const Eigen::Vector3d& x, const Eigen::Vector3d& y) {
  double sx, sy;
  if (!OnLine(*line, x, &sx) || !OnLine(*line, y, &sy)) return false;
  const double length = (line->q - line->p).norm();
  if (std::min(sx, sy) > length + kMergeTolerance || std::max(sx, sy) < -kMergeTolerance) return false;
  const Eigen::Vector3d& low = sx < sy ? x : y;
  const Eigen::Vector3d& high = sx < sy ? y : x;
  if (std::min(sx, sy) < 0.0) line->p = low;
  if (std::max(sx, sy) > length) line->q = high;
  line->direction = (line->q - line->p).normalized();
  return true;
}

// Intersects [*lo, *hi] with {s : alpha + beta s <= 0}.
void Restrict(double alpha, double beta, double* lo, double* hi) {
  if (beta > 0.0) {
    *hi = std::min(*hi, -alpha / beta);
  } else if (beta < 0.0) {
    *lo = std::max(*lo, -alpha / beta);
  } else if (alpha > 0.0) {
    *hi = *lo;  // empty
  }
}

}  // namespace

Surface MakeSurface(std::vector<Eigen::Vector3d> vertices, const Eigen::Vector3d& front,
                    const SurfaceTexture& texture, std::uint32_t line_edges) {
  const int n = static_cast<int>(vertices.size());
  if (n < 3) throw std::invalid_argument("MakeSurface: a polygon needs at least 3 vertices");
  // Newell's normal: robust for any planar polygon, its sign giving the winding.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) normal += vertices[i].cross(vertices[(i + 1) % n]);
  if (normal.norm() == 0.0) throw std::invalid_argument("MakeSurface: degenerate polygon");
  normal.normalize();
  Surface s;
  if (normal.dot(front) < 0.0) {
    std::reverse(vertices.begin(), vertices.end());
    normal = -normal;
    // Edge j of the reversed polygon is edge n - 2 - j (mod n) of the given one.
    std::uint32_t reversed = 0;
    for (int j = 0; j < n; ++j) {
      if (line_edges >> ((2 * n - 2 - j) % n) & 1u) reversed |= 1u << j;
    }
    line_edges = reversed;
  }
  s.vertices = std::move(vertices);
  s.normal = normal;
  s.texture_origin = s.vertices[0];
  s.axis_s = (s.vertices[1] - s.vertices[0]).normalized();
  s.axis_t = normal.cross(s.axis_s);
  s.texture = texture;
  s.line_edges = n >= 32 ? line_edges : line_edges & ((1u << n) - 1u);
  return s;
}

std::vector<Line3d> LinesFromSurfaces(const std::vector<Surface>& surfaces) {
  std::vector<MergedLine> lines;
  for (const Surface& surface : surfaces) {
    const std::size_t n = surface.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (!(surface.line_edges >> i & 1u)) continue;
      const Eigen::Vector3d &x = surface.vertices[i], &y = surface.vertices[(i + 1) % n];
      std::size_t merged_into = lines.size();
      for (std::size_t k = 0; k < lines.size() && merged_into == lines.size(); ++k) {
        if (TryMerge(&lines[k], x, y)) merged_into = k;
      }
      if (merged_into == lines.size()) {
        lines.push_back({x, y, (y - x).normalized()});
        continue;
      }
      // The longer line may now touch another one: absorb those too.
      for (std::size_t k = 0; k < lines.size();) {
        if (k != merged_into && TryMerge(&lines[merged_into], lines[k].p, lines[k].q)) {
          lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(k));
          if (k < merged_into) --merged_into;
          k = 0;
        } else {
          ++k;
        }
      }
    }
  }
  std::vector<Line3d> out;
  out.reserve(lines.size());
  for (const MergedLine& line : lines) out.push_back({line.p, line.q});
  return out;
}

Occluders::Occluders(const std::vector<Surface>& surfaces) {
  polygons_.reserve(surfaces.size());
  for (const Surface& s : surfaces) {
    Polygon p;
    p.normal = s.normal;
    p.offset = s.normal.dot(s.vertices[0]);
    p.centre = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& v : s.vertices) p.centre += v;
    p.centre /= static_cast<double>(s.vertices.size());
    p.radius = 0.0;
    for (const Eigen::Vector3d& v : s.vertices) p.radius = std::max(p.radius, (v - p.centre).norm());
    p.first_edge = static_cast<int>(edges_.size());
    p.edge_count = static_cast<int>(s.vertices.size());
    for (std::size_t i = 0; i < s.vertices.size(); ++i) {
      const Eigen::Vector3d& v = s.vertices[i];
      const Eigen::Vector3d m = (s.vertices[(i + 1) % s.vertices.size()] - v).cross(s.normal).normalized();
      edges_.push_back({m, m.dot(v)});
    }
    polygons_.push_back(p);
  }
}

void Occluders::VisibleParts(const Eigen::Vector3d& eye, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             std::vector<Eigen::Vector2d>* parts) const {
  parts->clear();
  const Eigen::Vector3d ea = a - eye, ab = b - a;
  // Only a polygon that meets the triangle (eye, a, b) can cross a sight line: culled by its
  // bounding sphere against the triangle's plane, the wedge between the sight lines to a and
  // b, and the distance of the farther endpoint.
  const Eigen::Vector3d eb = b - eye;
  Eigen::Vector3d normal = ea.cross(eb);
  const double normal_norm = normal.norm();
  const bool flat = normal_norm <= 1e-12 * ea.norm() * eb.norm();  // eye on the segment's line
  if (!flat) normal /= normal_norm;
  Eigen::Vector3d side_a = normal.cross(ea), side_b = normal.cross(eb);
  if (!flat) {
    side_a.normalize();
    side_b.normalize();
    if (side_a.dot(eb) < 0.0) side_a = -side_a;
    if (side_b.dot(ea) < 0.0) side_b = -side_b;
  }
  const double reach = std::max(ea.norm(), eb.norm());
  for (const Polygon& poly : polygons_) {
    const Eigen::Vector3d c = poly.centre - eye;
    if (c.norm() - poly.radius > reach) continue;
    if (!flat && (std::abs(normal.dot(c)) > poly.radius || side_a.dot(c) < -poly.radius ||
                  side_b.dot(c) < -poly.radius)) {
      continue;
    }
    // The sight line to X(s) is eye + t (ea + s ab), t in (0, 1); it meets the plane at
    // t = h / D(s) with D(s) = D0 + s D1 linear in s.
    const double h = poly.offset - poly.normal.dot(eye);
    if (h == 0.0) continue;  // the eye in the plane: the polygon is seen edge-on
    const double d0 = poly.normal.dot(ea), d1 = poly.normal.dot(ab);
    double cuts[3] = {0.0, 1.0, 1.0};
    int pieces = 1;
    if (d1 != 0.0) {
      const double root = -d0 / d1;
      if (root > 0.0 && root < 1.0) {
        cuts[1] = root;
        pieces = 2;
      }
    }
    for (int k = 0; k < pieces; ++k) {
      double lo = cuts[k], hi = cuts[k + 1];
      const double d_mid = d0 + 0.5 * (lo + hi) * d1;
      if (d_mid == 0.0) continue;
      const double sigma = d_mid > 0.0 ? 1.0 : -1.0;
      if (sigma * h <= 0.0) continue;  // the plane is behind the eye on this piece
      // In front of X: h / D < 1 - margin.
      Restrict(sigma * (h - (1.0 - kDepthMargin) * d0), -sigma * (1.0 - kDepthMargin) * d1, &lo, &hi);
      // Inside every edge: m . Y <= c - margin, multiplied by D (sign sigma).
      for (int e = poly.first_edge; e < poly.first_edge + poly.edge_count && lo < hi; ++e) {
        const EdgePlane& edge = edges_[e];
        const double g = edge.m.dot(eye) - edge.c + kInsideMargin;
        Restrict(sigma * (g * d0 + h * edge.m.dot(ea)), sigma * (g * d1 + h * edge.m.dot(ab)), &lo, &hi);
      }
      if (lo < hi) parts->emplace_back(lo, hi);
    }
  }
  // The complement of the hidden intervals in [0, 1].
  std::sort(parts->begin(), parts->end(), [](const Eigen::Vector2d& x, const Eigen::Vector2d& y) { return x[0] < y[0]; });
  std::size_t count = 0;
  double start = 0.0;
  const std::size_t hidden = parts->size();
  for (std::size_t i = 0; i < hidden; ++i) {
    const Eigen::Vector2d interval = (*parts)[i];
    if (interval[0] > start) (*parts)[count++] = Eigen::Vector2d(start, interval[0]);
    start = std::max(start, interval[1]);
  }
  if (start < 1.0) {
    if (count < parts->size()) {
      (*parts)[count++] = Eigen::Vector2d(start, 1.0);
    } else {
      parts->emplace_back(start, 1.0);
      ++count;
    }
  }
  parts->resize(count);
}

}  // namespace slt
