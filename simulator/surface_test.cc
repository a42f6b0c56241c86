#include "simulator/surface.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "simulator/random_draws.h"

namespace slt {
namespace {

using Eigen::Vector3d;

// The square [x0, x1] x [y0, y1] at depth z, facing the camera at the origin (-z).
Surface Square(double x0, double y0, double x1, double y1, double z, std::uint32_t edges = ~0u) {
  return MakeSurface({{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}}, -Vector3d::UnitZ(), {}, edges);
}

TEST(Surface, MakeSurfaceOrientsTowardsTheFrontAndKeepsTheEdgeFlags) {
  // Given clockwise as seen from -z: reversed, and edge 0 (the bottom, y = 0) still flagged.
  const Surface s = Square(0.0, 0.0, 1.0, 1.0, 2.0, 0b0001u);
  EXPECT_NEAR((s.normal + Vector3d::UnitZ()).norm(), 0.0, 1e-15);
  const std::vector<Line3d> lines = LinesFromSurfaces({s});
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].p.y(), 0.0);
  EXPECT_EQ(lines[0].q.y(), 0.0);
  EXPECT_EQ(std::abs(lines[0].q.x() - lines[0].p.x()), 1.0);
}

TEST(Surface, SharedAndCollinearEdgesAreOneLine) {
  // A cube's six faces give its twelve edges.
  std::vector<Surface> cube;
  for (int axis = 0; axis < 3; ++axis) {
    for (const double side : {0.0, 1.0}) {
      std::vector<Vector3d> v(4, Vector3d::Zero());
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      const double corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      for (int k = 0; k < 4; ++k) {
        v[k][axis] = side;
        v[k][u] = corners[k][0];
        v[k][w] = corners[k][1];
      }
      cube.push_back(MakeSurface(v, Vector3d::Unit(axis) * (side - 0.5), {}));
    }
  }
  EXPECT_EQ(LinesFromSurfaces(cube).size(), 12u);
  // Two squares side by side: their bottom and top edges continue each other, the shared
  // side is one line: 3 vertical + 2 horizontal lines.
  const std::vector<Line3d> lines = LinesFromSurfaces({Square(0, 0, 1, 1, 2), Square(1, 0, 3, 1, 2)});
  EXPECT_EQ(lines.size(), 5u);
  int long_ones = 0;
  for (const Line3d& l : lines) long_ones += std::abs((l.q - l.p).norm() - 3.0) < 1e-12;
  EXPECT_EQ(long_ones, 2);
  // Parallel edges 1 mm apart stay two lines.
  EXPECT_EQ(LinesFromSurfaces({Square(0, 0, 1, 1, 2), Square(0, 1.001, 1, 2, 2)}).size(), 8u);
}

TEST(Surface, AnOccluderHidesTheMiddleOfASegmentBehindIt) {
  // A segment along x at depth 4 behind a square [-0.5, 0.5] at depth 2: seen from the origin
  // the square covers x in [-1, 1] at depth 4.
  const Occluders occluders({Square(-0.5, -0.5, 0.5, 0.5, 2.0)});
  std::vector<Eigen::Vector2d> parts;
  occluders.VisibleParts(Vector3d::Zero(), {-3.0, 0.0, 4.0}, {3.0, 0.0, 4.0}, &parts);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_NEAR(parts[0][0], 0.0, 1e-12);
  EXPECT_NEAR(parts[0][1], 2.0 / 6.0, 1e-9);
  EXPECT_NEAR(parts[1][0], 4.0 / 6.0, 1e-9);
  EXPECT_NEAR(parts[1][1], 1.0, 1e-12);
  // In front of the square, or seen from behind its plane, nothing is hidden.
  occluders.VisibleParts(Vector3d::Zero(), {-3.0, 0.0, 1.0}, {3.0, 0.0, 1.0}, &parts);
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0], Eigen::Vector2d(0.0, 1.0));
  occluders.VisibleParts({0.0, 0.0, 5.0}, {-3.0, 0.0, 4.0}, {3.0, 0.0, 4.0}, &parts);
  ASSERT_EQ(parts.size(), 1u);
  // A segment on the square's own edge or in its plane is not hidden by it.
  occluders.VisibleParts({0.1, 0.2, 0.0}, {-0.5, 0.5, 2.0}, {0.5, 0.5, 2.0}, &parts);
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0], Eigen::Vector2d(0.0, 1.0));
  occluders.VisibleParts({0.1, 0.2, 0.0}, {-0.2, 0.1, 2.0}, {0.3, -0.1, 2.0}, &parts);
  ASSERT_EQ(parts.size(), 1u);
  // Entirely behind: nothing visible.
  occluders.VisibleParts(Vector3d::Zero(), {-0.5, 0.0, 4.0}, {0.5, 0.0, 4.0}, &parts);
  EXPECT_TRUE(parts.empty());
}

// Brute force: is the point hidden from the eye by any of the polygons?
bool HiddenByRayTest(const std::vector<Surface>& surfaces, const Vector3d& eye, const Vector3d& x) {
  for (const Surface& s : surfaces) {
    const double denominator = s.normal.dot(x - eye);
    if (denominator == 0.0) continue;
    const double t = s.normal.dot(s.vertices[0] - eye) / denominator;
    if (!(t > 0.0 && t < 1.0 - 1e-6)) continue;
    const Vector3d y = eye + t * (x - eye);
    bool inside = true;
    for (std::size_t i = 0; i < s.vertices.size() && inside; ++i) {
      const Vector3d& v = s.vertices[i];
      const Vector3d m = (s.vertices[(i + 1) % s.vertices.size()] - v).cross(s.normal).normalized();
      inside = m.dot(y - v) < -1e-9;
    }
    if (inside) return true;
  }
  return false;
}

TEST(Surface, VisiblePartsAgreeWithRayTestsOnRandomScenes) {
  SplitMix64 g(17);
  std::size_t hidden_samples = 0, samples = 0;
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<Surface> surfaces;
    for (int k = 0; k < 6; ++k) {
      // Random triangles and quads around the unit cube, either way round.
      const Vector3d centre(Uniform(g, -1, 1), Uniform(g, -1, 1), Uniform(g, -1, 1));
      const Vector3d u = UniformUnitVector(g), w = u.cross(UniformUnitVector(g)).normalized();
      const Vector3d v = w.cross(u);
      const int n = 3 + k % 2;
      std::vector<Vector3d> vertices;
      for (int i = 0; i < n; ++i) {
        const double angle = 2.0 * M_PI * i / n;
        vertices.push_back(centre + 0.6 * (std::cos(angle) * u + std::sin(angle) * v));
      }
      surfaces.push_back(MakeSurface(vertices, UniformUnitVector(g), {}));
    }
    const Occluders occluders(surfaces);
    const Vector3d eye = 3.0 * UniformUnitVector(g);
    const Vector3d a = 1.5 * UniformUnitVector(g), b = 1.5 * UniformUnitVector(g);
    std::vector<Eigen::Vector2d> parts;
    occluders.VisibleParts(eye, a, b, &parts);
    for (int i = 0; i <= 400; ++i) {
      const double s = i / 400.0;
      bool visible = false, near_end = false;
      for (const Eigen::Vector2d& part : parts) {
        visible |= s >= part[0] && s <= part[1];
        near_end |= std::abs(s - part[0]) < 1e-6 || std::abs(s - part[1]) < 1e-6;
      }
      if (near_end) continue;
      const bool hidden = HiddenByRayTest(surfaces, eye, a + s * (b - a));
      EXPECT_EQ(visible, !hidden) << "trial " << trial << " s " << s;
      hidden_samples += hidden;
      ++samples;
    }
  }
  // The random scenes do hide things, and not everything.
  EXPECT_GT(hidden_samples, samples / 20);
  EXPECT_LT(hidden_samples, samples / 2);
}

}  // namespace
}  // namespace slt
