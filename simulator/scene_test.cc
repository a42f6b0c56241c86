#include "simulator/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "simulator/motion.h"

namespace slt {
namespace {

bool SameLines(const std::vector<Line3d>& a, const std::vector<Line3d>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].p != b[i].p || a[i].q != b[i].q) return false;
  }
  return true;
}

TEST(Scene, PaperLinesHaveTheConfiguredLengthsAndPlaces) {
  SceneConfig c;
  const std::vector<Line3d> lines = MakeScene(c, 1).lines;
  ASSERT_EQ(lines.size(), 40u);
  for (const Line3d& line : lines) {
    const double length = (line.q - line.p).norm();
    EXPECT_GE(length, c.paper.min_length_m);
    EXPECT_LE(length, c.paper.max_length_m);
    const Eigen::Vector3d offset = 0.5 * (line.p + line.q) - c.paper.box_center_m;
    EXPECT_TRUE((offset.cwiseAbs().array() <= 0.5 * c.paper.box_size_m.array() + 1e-12).all());
  }
}

TEST(Scene, PaperScenesWithFewerLinesAreNested) {
  SceneConfig c;
  const std::vector<Line3d> all = MakeScene(c, 5).lines;
  c.paper.lines = 10;
  const std::vector<Line3d> some = MakeScene(c, 5).lines;
  EXPECT_TRUE(SameLines(some, std::vector<Line3d>(all.begin(), all.begin() + 10)));
  EXPECT_FALSE(SameLines(MakeScene(c, 6).lines, some));
}

double DirectionSine(const Line3d& a, const Line3d& b) {
  return (a.q - a.p).normalized().cross((b.q - b.p).normalized()).norm();
}
double DirectionCosine(const Line3d& a, const Line3d& b) {
  return std::abs((a.q - a.p).normalized().dot((b.q - b.p).normalized()));
}

TEST(Scene, PaperCuboidsComeFirstAndLeaveTheRandomLinesAlone) {
  SceneConfig c;
  const std::vector<Line3d> plain = MakeScene(c, 3).lines;
  c.paper.cuboid_fraction = 0.3;
  const std::vector<Line3d> mixed = MakeScene(c, 3).lines;
  ASSERT_EQ(mixed.size(), 40u);
  // 12 cuboid edges, then the first 28 lines of the plain scene, drawn as before.
  EXPECT_TRUE(SameLines(std::vector<Line3d>(mixed.begin() + 12, mixed.end()),
                        std::vector<Line3d>(plain.begin(), plain.begin() + 28)));
  for (int i = 0; i < 12; ++i) {
    const double length = (mixed[i].q - mixed[i].p).norm();
    EXPECT_GE(length, c.paper.min_length_m - 1e-12);
    EXPECT_LE(length, c.paper.max_length_m + 1e-12);
  }
  // A rectangle: opposite edges parallel, adjacent ones orthogonal and joined.
  EXPECT_LT(DirectionSine(mixed[0], mixed[2]), 1e-12);
  EXPECT_LT(DirectionSine(mixed[1], mixed[3]), 1e-12);
  EXPECT_LT(DirectionCosine(mixed[0], mixed[1]), 1e-12);
  for (int i = 0; i < 4; ++i) EXPECT_LT((mixed[i].q - mixed[(i + 1) % 4].p).norm(), 1e-12);
  // A box corner cut to 8 of its 9 edges: three orthogonal edges from one vertex, each of the
  // other five parallel to one of them.
  for (int i = 4; i < 7; ++i) {
    EXPECT_LT((mixed[i].p - mixed[4].p).norm(), 1e-12);
    for (int j = 4; j < i; ++j) EXPECT_LT(DirectionCosine(mixed[i], mixed[j]), 1e-12);
  }
  for (int i = 7; i < 12; ++i) {
    const double sine = std::min({DirectionSine(mixed[i], mixed[4]), DirectionSine(mixed[i], mixed[5]),
                                  DirectionSine(mixed[i], mixed[6])});
    EXPECT_LT(sine, 1e-12) << "line " << i;
  }
  // Other seeds, other cuboids.
  EXPECT_FALSE(SameLines(MakeScene(c, 4).lines, mixed));
  c.paper.cuboid_fraction = 1.0;
  EXPECT_EQ(MakeScene(c, 3).lines.size(), 40u);
}

// Structured scenes: everything inside the room, nothing degenerate, ids shuffled by the seed.
void CheckStructured(const SceneConfig& c, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const std::vector<Line3d> lines = MakeScene(c, 1).lines;
  EXPECT_GT(lines.size(), 100u);
  for (const Line3d& line : lines) {
    EXPECT_GT((line.q - line.p).norm(), 0.005);  // the thinnest boards and bezels are 1 cm
    for (const Eigen::Vector3d& x : {line.p, line.q}) {
      EXPECT_TRUE((x.array() >= lo.array() - 1e-9).all() && (x.array() <= hi.array() + 1e-9).all())
          << x.transpose();
    }
  }
  EXPECT_TRUE(SameLines(MakeScene(c, 1).lines, lines));
  const std::vector<Line3d> other = MakeScene(c, 2).lines;
  EXPECT_FALSE(SameLines(other, lines));
}

TEST(Scene, RoomStaysInsideItsWalls) {
  SceneConfig c;
  c.type = SceneType::kRoom;
  const RoomSceneConfig& r = c.room;
  // The window pane and the door leaves are set up to 10 cm into the walls.
  CheckStructured(c, {-0.5 * r.width_m - 0.1, r.camera_height_m - r.height_m, -0.4 * r.depth_m - 0.1},
                  {0.5 * r.width_m + 0.1, r.camera_height_m, 0.6 * r.depth_m + 0.1});
}

TEST(Scene, CorridorStaysInsideItsWalls) {
  SceneConfig c;
  c.type = SceneType::kCorridor;
  const CorridorSceneConfig& r = c.corridor;
  // Door leaves are set 4 cm, the far window 8 cm into the walls.
  CheckStructured(c, {-0.5 * r.width_m - 0.08, r.camera_height_m - r.height_m, -2.0 - 0.08},
                  {0.5 * r.width_m + 0.08, r.camera_height_m, r.length_m - 2.0 + 0.08});
}

TEST(Scene, StreetStaysInsideItsStreetsAndHasLinesOfEveryDirection) {
  SceneConfig c;
  c.type = SceneType::kStreet;
  const StreetSceneConfig& r = c.street;
  const double x0 = -r.lane_offset_m;
  // Between the facades of the two streets and their end walls (plus what stands out of them),
  // from the road to the highest roof (4.4 m + 5 storeys of 3.4 m + 1.2 m).
  CheckStructured(c, {x0 - r.cross_length_m - 0.5, r.camera_height_m - 24.0, -30.5},
                  {x0 + r.cross_length_m + 0.5, r.camera_height_m, r.crossing_at_m + 8.5 + r.far_length_m + 0.5});
  const std::vector<Line3d> lines = MakeScene(c, 1).lines;
  EXPECT_GT(lines.size(), 3000u);
  int along_x = 0, along_y = 0, along_z = 0, oblique = 0;
  for (const Line3d& line : lines) {
    const Eigen::Vector3d d = (line.q - line.p).normalized().cwiseAbs();
    (d.x() > 1.0 - 1e-9 ? along_x : d.y() > 1.0 - 1e-9 ? along_y : d.z() > 1.0 - 1e-9 ? along_z : oblique) += 1;
  }
  EXPECT_GT(along_x, 500);
  EXPECT_GT(along_y, 500);
  EXPECT_GT(along_z, 500);
  EXPECT_GT(oblique, 20);  // awnings
}

// Distance from x to a convex planar polygon.
double DistanceToPolygon(const Eigen::Vector3d& x, const Surface& s) {
  const double height = s.normal.dot(x - s.vertices[0]);
  const Eigen::Vector3d on_plane = x - height * s.normal;
  bool inside = true;
  double edge_distance = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < s.vertices.size(); ++i) {
    const Eigen::Vector3d &a = s.vertices[i], &b = s.vertices[(i + 1) % s.vertices.size()];
    if ((b - a).cross(on_plane - a).dot(s.normal) < 0.0) inside = false;
    const double t = std::clamp((x - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    edge_distance = std::min(edge_distance, (a + t * (b - a) - x).norm());
  }
  return inside ? std::abs(height) : edge_distance;
}

TEST(Scene, TheCarProfileDrivesThroughTheStreetClearOfEverything) {
  // The default car route in the default street, and the route that starts in the turn of a
  // crossing 20 m ahead (frontend/configs/street_turn_start.json): the camera's centre at every
  // frame keeps 1.3 m from every surface (a car's half width and more), the road's 1.65 m below
  // aside.
  for (const auto& [crossing_at_m, straight_m] : {std::pair{50.0, 31.25}, std::pair{20.0, 1.25}}) {
    SceneConfig c;
    c.type = SceneType::kStreet;
    c.street.crossing_at_m = crossing_at_m;
    const Scene scene = MakeScene(c, 1);
    MotionConfig motion;
    motion.profile = MotionProfile::kCar;
    motion.car.straight_m = straight_m;
    const Trajectory t = MakeTrajectory(motion, 200, 10.0, 1);
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < t.size(); k += 2) {
      const Eigen::Vector3d centre = t[k].world_from_cam.translation;
      for (const Surface& s : scene.surfaces) {
        if (s.normal.y() < -0.99 && s.vertices[0].y() >= c.street.camera_height_m - 0.01) continue;  // the road
        nearest = std::min(nearest, DistanceToPolygon(centre, s));
      }
    }
    EXPECT_GT(nearest, 1.3) << "crossing at " << crossing_at_m << " m";
  }
}

}  // namespace
}  // namespace slt
