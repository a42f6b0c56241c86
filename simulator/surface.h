// Planar textured surfaces: what the scenes are made of. The simulator's 3-D line segments are
// the visible edges of these surfaces (polygon boundaries with contrast: box edges, frames,
// texture boundaries), and which part of a segment a camera sees is decided against them
// (occlusion). The renderer (render/) draws them. docs/simulation.md ("Scenes") and
// docs/rendering.md describe the model.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace slt {

// A 3-D line segment, endpoints in world coordinates.
struct Line3d {
  Eigen::Vector3d p;
  Eigen::Vector3d q;
};

// The procedural patterns a surface can carry (render/texture.h evaluates them).
enum class TexturePattern {
  kFlat,     // uniform
  kMottled,  // smooth isotropic noise (paint, plaster, cardboard)
  kGrain,    // noise stretched along s (wood, brushed surfaces)
};

// Reflectance on the surface: albedo * (1 + contrast * pattern(s / scale_m, t / scale_m)) with
// pattern in [-1, 1] and (s, t) the surface's texture coordinates in metres.
struct SurfaceTexture {
  double albedo = 0.5;
  double contrast = 0.0;
  TexturePattern pattern = TexturePattern::kFlat;
  double scale_m = 0.1;
  std::uint64_t seed = 0;  // places this surface's piece of the pattern (offset)
};

// A convex planar polygon. Its front is the side `normal` points to; a one-sided surface is
// seen only from the front (walls, box faces), a two-sided one from both (the paper scene's
// bars).
struct Surface {
  std::vector<Eigen::Vector3d> vertices;  // counter-clockwise seen from the front, >= 3
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  // Texture coordinates of a point X: s = axis_s . (X - texture_origin), t = axis_t . (...).
  // Pieces of one wall share the frame, so the pattern runs on across them without a seam.
  Eigen::Vector3d texture_origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_s = Eigen::Vector3d::UnitX();
  Eigen::Vector3d axis_t = Eigen::Vector3d::UnitY();
  SurfaceTexture texture;
  // Bit i set: the edge vertices[i] -> vertices[i + 1] is a line of the scene (a boundary with
  // contrast). Seams between pieces of one wall are not.
  std::uint32_t line_edges = 0;
  bool two_sided = false;
};

// A polygon from its vertices (convex, planar, in order either way round): the order is made
// counter-clockwise as seen from the side `front` points to, and the normal computed.
Surface MakeSurface(std::vector<Eigen::Vector3d> vertices, const Eigen::Vector3d& front,
                    const SurfaceTexture& texture, std::uint32_t line_edges = ~0u);

// The scene's lines: every edge flagged in line_edges, with collinear edges that overlap or
// touch merged into one segment (a box edge shared by two faces, a floor line running on past
// a door jamb). Order: first appearance.
std::vector<Line3d> LinesFromSurfaces(const std::vector<Surface>& surfaces);

// Occlusion against a fixed set of surfaces. A point X is hidden from an eye E when a surface
// crosses the open segment E-X strictly in front of X (by more than 1e-6 of the distance) and
// strictly inside its polygon (by more than 1e-9 m): a segment lying on a surface's edge or in
// its plane is not hidden by it. Back faces occlude too (a closed box hides what is behind it
// from any side).
class Occluders {
 public:
  explicit Occluders(const std::vector<Surface>& surfaces);

  // The parts of the segment X(s) = a + s (b - a), s in [0, 1], seen from `eye` (all in world
  // coordinates): sorted, disjoint [s0, s1] intervals, replacing the contents of `parts`.
  // Exact up to rounding: for a convex polygon the hidden set of s is an interval whose ends
  // solve linear equations (the ray-plane parameter is a ratio of linear functions of s).
  void VisibleParts(const Eigen::Vector3d& eye, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                    std::vector<Eigen::Vector2d>* parts) const;

 private:
  struct Polygon {
    Eigen::Vector3d normal;
    double offset;  // normal . X = offset on the plane
    Eigen::Vector3d centre;
    double radius;
    int first_edge;
    int edge_count;
  };
  // A hierarchy of bounding spheres over the polygons (median splits of their centres along
  // the widest axis, up to kLeafSize per leaf): a node whose sphere misses the sight triangle
  // culls all its polygons at once, so a query costs about the logarithm of the scene's size
  // and what the triangle meets (the street's thousands of surfaces).
  struct Node {
    Eigen::Vector3d centre;
    double radius;
    int first;  // leaf: polygons_[first, first + count); inner: children first and first + 1
    int count;  // 0 for an inner node
  };
  // Fills nodes_[index] with polygons_[first, first + count), reordering them.
  void Build(int index, int first, int count);
  // The part of VisibleParts for one polygon: appends its hidden interval(s) of s to `hidden`.
  void HiddenParts(const Polygon& poly, const Eigen::Vector3d& eye, const Eigen::Vector3d& ea,
                   const Eigen::Vector3d& ab, std::vector<Eigen::Vector2d>* hidden) const;
  std::vector<Node> nodes_;
  // In-plane unit outward normal m and offset c of one polygon edge: m . X <= c inside.
  struct EdgePlane {
    Eigen::Vector3d m;
    double c;
  };
  std::vector<Polygon> polygons_;
  std::vector<EdgePlane> edges_;
};

}  // namespace slt
