#include "simulator/surface.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include "common/random.h"

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
// The grid of LinesFromSurfaces (m): far coarser than the merge tolerance, far finer than the
// spacing of distinct parallel lines that share a foot point's neighbourhood.
constexpr double kFootCell = 0.01;
// Polygons per leaf of Occluders' sphere hierarchy.
constexpr int kLeafSize = 8;

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
  // Collinear edges have (within rounding) the same foot point, the point of their line nearest
  // the origin: lines are found by the cells of a 1 cm grid around it (the 27 cells about an
  // edge's own), not by comparing every edge with every line. The merges are those of a scan
  // over all lines in creation order (the first line an edge merges with takes it; a grown line
  // absorbs the first line it now touches, again until none), so the output does not depend on
  // the grid.
  std::vector<MergedLine> lines;
  std::vector<bool> alive;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells;
  const auto cell_of = [](const Eigen::Vector3d& x, const Eigen::Vector3d& direction) {
    const Eigen::Vector3d foot = x - x.dot(direction) * direction;
    return Eigen::Vector3d((foot / kFootCell).array().floor());
  };
  const auto key = [](const Eigen::Vector3d& cell) {
    std::uint64_t k = 0;
    for (int i = 0; i < 3; ++i) k = MixSeed(k ^ static_cast<std::uint64_t>(static_cast<std::int64_t>(cell[i])));
    return k;
  };
  std::vector<std::size_t> candidates;
  for (const Surface& surface : surfaces) {
    const std::size_t n = surface.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (!(surface.line_edges >> i & 1u)) continue;
      const Eigen::Vector3d &x = surface.vertices[i], &y = surface.vertices[(i + 1) % n];
      const Eigen::Vector3d cell = cell_of(x, (y - x).normalized());
      candidates.clear();
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dz = -1; dz <= 1; ++dz) {
            const auto found = cells.find(key(cell + Eigen::Vector3d(dx, dy, dz)));
            if (found != cells.end()) candidates.insert(candidates.end(), found->second.begin(), found->second.end());
          }
        }
      }
      std::sort(candidates.begin(), candidates.end());
      candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
      std::size_t merged_into = lines.size();
      for (const std::size_t k : candidates) {
        if (alive[k] && TryMerge(&lines[k], x, y)) {
          merged_into = k;
          break;
        }
      }
      if (merged_into == lines.size()) {
        cells[key(cell)].push_back(lines.size());
        lines.push_back({x, y, (y - x).normalized()});
        alive.push_back(true);
        continue;
      }
      // The longer line may now touch another one: absorb those too.
      for (bool absorbed = true; absorbed;) {
        absorbed = false;
        for (const std::size_t k : candidates) {
          if (k != merged_into && alive[k] && TryMerge(&lines[merged_into], lines[k].p, lines[k].q)) {
            alive[k] = false;
            absorbed = true;
            break;
          }
        }
      }
    }
  }
  std::vector<Line3d> out;
  out.reserve(lines.size());
  for (std::size_t k = 0; k < lines.size(); ++k) {
    if (alive[k]) out.push_back({lines[k].p, lines[k].q});
  }
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
  if (!polygons_.empty()) {
    nodes_.emplace_back();
    Build(0, 0, static_cast<int>(polygons_.size()));
  }
}

void Occluders::Build(int index, int first, int count) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  Eigen::Vector3d centre_lo = lo, centre_hi = hi;
  for (int i = first; i < first + count; ++i) {
    const Polygon& p = polygons_[i];
    lo = lo.cwiseMin(p.centre - Eigen::Vector3d::Constant(p.radius));
    hi = hi.cwiseMax(p.centre + Eigen::Vector3d::Constant(p.radius));
    centre_lo = centre_lo.cwiseMin(p.centre);
    centre_hi = centre_hi.cwiseMax(p.centre);
  }
  Node node;
  node.centre = 0.5 * (lo + hi);
  node.radius = 0.0;
  for (int i = first; i < first + count; ++i) {
    node.radius = std::max(node.radius, (polygons_[i].centre - node.centre).norm() + polygons_[i].radius);
  }
  node.first = first;
  node.count = count;
  if (count <= kLeafSize) {
    nodes_[index] = node;
    return;
  }
  int axis = 0;
  (centre_hi - centre_lo).maxCoeff(&axis);
  const int half = count / 2;
  // Ties broken by the polygon's place in the scene, so the split does not depend on the
  // standard library's nth_element.
  std::nth_element(polygons_.begin() + first, polygons_.begin() + first + half, polygons_.begin() + first + count,
                   [axis](const Polygon& a, const Polygon& b) {
                     return a.centre[axis] < b.centre[axis] ||
                            (a.centre[axis] == b.centre[axis] && a.first_edge < b.first_edge);
                   });
  node.first = static_cast<int>(nodes_.size());
  node.count = 0;
  nodes_[index] = node;
  nodes_.emplace_back();
  nodes_.emplace_back();
  Build(node.first, first, half);
  Build(node.first + 1, first + half, count - half);
}

void Occluders::HiddenParts(const Polygon& poly, const Eigen::Vector3d& eye, const Eigen::Vector3d& ea,
                            const Eigen::Vector3d& ab, std::vector<Eigen::Vector2d>* hidden) const {
  // The sight line to X(s) is eye + t (ea + s ab), t in (0, 1); it meets the plane at
  // t = h / D(s) with D(s) = D0 + s D1 linear in s.
  const double h = poly.offset - poly.normal.dot(eye);
  if (h == 0.0) return;  // the eye in the plane: the polygon is seen edge-on
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
    if (lo < hi) hidden->emplace_back(lo, hi);
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
  // A sphere that cannot meet the triangle (eye, a, b): beyond the farther endpoint, off its
  // plane, or outside the wedge between the sight lines.
  const auto culled = [&](const Eigen::Vector3d& centre, double radius) {
    const Eigen::Vector3d c = centre - eye;
    if (c.norm() - radius > reach) return true;
    return !flat && (std::abs(normal.dot(c)) > radius || side_a.dot(c) < -radius || side_b.dot(c) < -radius);
  };
  int stack[64];
  int depth = 0;
  if (!nodes_.empty()) stack[depth++] = 0;
  while (depth > 0) {
    const Node& node = nodes_[stack[--depth]];
    if (culled(node.centre, node.radius)) continue;
    if (node.count == 0) {
      stack[depth++] = node.first + 1;
      stack[depth++] = node.first;
      continue;
    }
    for (int i = node.first; i < node.first + node.count; ++i) {
      const Polygon& poly = polygons_[i];
      if (!culled(poly.centre, poly.radius)) HiddenParts(poly, eye, ea, ab, parts);
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
