#include "render/rasterizer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "render/sequence_renderer.h"
#include "simulator/motion.h"
#include "simulator/surface.h"

namespace slt {
namespace {

// The camera model switched off: what is left is the rasteriser's own image (exposure
// variation stays: a gain does not move an edge).
const nlohmann::json kSharpImages = {
    {"read_noise", 0.0}, {"shot_noise", 0.0}, {"defocus_blur_px", 0.0}, {"vignetting", 0.0}};

SimulationConfig SharpConfig(const char* scene, int frames) {
  const nlohmann::json j = {{"scene", {{"type", scene}}},
                            {"frames", frames},
                            {"noise", {{"endpoint_px", 0.0}}},
                            {"observation", {{"clip_to_image", true}, {"occlusion", true}}},
                            {"images", kSharpImages}};
  return SimulationConfigFromJson(j, "test");
}

// Edges with a smaller step (grey levels) between their sides are not measured: there the
// surfaces' textures, whose own gradients reach a few grey levels per pixel, can move the peak.
constexpr double kMinStep = 30.0;

double Bilinear(const cv::Mat& image, const Eigen::Vector2d& p) {
  const int x = static_cast<int>(std::floor(p.x())), y = static_cast<int>(std::floor(p.y()));
  const double fx = p.x() - x, fy = p.y() - y;
  const auto at = [&](int xx, int yy) { return static_cast<double>(image.at<unsigned char>(yy, xx)); };
  return (1 - fy) * ((1 - fx) * at(x, y) + fx * at(x + 1, y)) + fy * ((1 - fx) * at(x, y + 1) + fx * at(x + 1, y + 1));
}

double DistanceToSegment(const Eigen::Vector2d& x, const Segment2d& s) {
  const Eigen::Vector2d a = s.head<2>(), b = s.tail<2>();
  const double t = std::clamp((x - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
  return (a + t * (b - a) - x).norm();
}

// Both ends of `edge` within 0.01 px of the line of `segment`: a piece of the same 3-D line (an
// edge of the other face of a box edge, a merged piece). A distinct edge nearer than that is
// another edge within 4 px (seen at a grazing angle, a window frame's band is under a pixel).
bool Collinear(const Segment2d& segment, const Segment2d& edge) {
  const Eigen::Vector2d a = segment.head<2>(), n = Eigen::Vector2d(a.y() - segment[3], segment[2] - a.x()).normalized();
  return std::abs(n.dot(edge.head<2>() - a)) < 0.01 && std::abs(n.dot(edge.tail<2>() - a)) < 0.01;
}

// Every polygon edge of the scene in front of the camera, projected: what can put another
// step next to a segment (including the edges that are not lines, like the far side of a
// paper-scene bar, and hidden ones).
std::vector<Segment2d> ProjectedEdges(const std::vector<Surface>& surfaces, const Rigid3d& cam_from_world,
                                      const PinholeCamera& camera) {
  std::vector<Segment2d> edges;
  for (const Surface& s : surfaces) {
    for (std::size_t i = 0; i < s.vertices.size(); ++i) {
      Eigen::Vector3d p = cam_from_world * s.vertices[i], q = cam_from_world * s.vertices[(i + 1) % s.vertices.size()];
      // The part in front of the camera (a curb or a parked car beside it reaches behind).
      if (p.z() < 0.05 && q.z() < 0.05) continue;
      if (p.z() < 0.05) p = q + (p - q) * (q.z() - 0.05) / (q.z() - p.z());
      if (q.z() < 0.05) q = p + (q - p) * (p.z() - 0.05) / (p.z() - q.z());
      Segment2d e;
      e << camera.Project(p), camera.Project(q);
      if ((e.head<2>() - e.tail<2>()).norm() > 1e-6) edges.push_back(e);
    }
  }
  return edges;
}

struct EdgeCheck {
  int samples = 0;        // points along the segments with a step across them
  int crowded = 0;        // points with another edge within 4 px: no single edge to measure
  int weak = 0;           // points without one (two sides alike)
  int off = 0;            // points whose gradient peak is more than 0.25 px from the segment
  double worst = 0.0;
};

// Along the segment, every 2 px (3 px clear of its ends and 4 px of the border): the profile
// across it at 1 px steps (bilinear), its central-difference gradient and the parabola through
// the gradient's peak and neighbours. Where the two sides differ by 20 grey levels or more, the
// peak must lie within 0.25 px of the segment.
void CheckEdge(const cv::Mat& image, const Segment2d& segment, const std::vector<Segment2d>& edges,
               EdgeCheck* check) {
  const Eigen::Vector2d a = segment.head<2>(), b = segment.tail<2>();
  const double length = (b - a).norm();
  const Eigen::Vector2d d = (b - a) / length, n(-d.y(), d.x());
  for (double t = 3.0; t <= length - 3.0; t += 2.0) {
    const Eigen::Vector2d c = a + t * d;
    if (c.x() < 5 || c.y() < 5 || c.x() > image.cols - 6 || c.y() > image.rows - 6) continue;
    bool crowded = false;
    for (std::size_t j = 0; j < edges.size() && !crowded; ++j) {
      crowded = DistanceToSegment(c, edges[j]) < 4.0 && !Collinear(segment, edges[j]);
    }
    if (crowded) {
      ++check->crowded;
      continue;
    }
    double profile[7];
    for (int i = 0; i < 7; ++i) profile[i] = Bilinear(image, c + (i - 3) * n);
    if (std::abs(profile[6] - profile[0]) < kMinStep) {
      ++check->weak;
      continue;
    }
    double gradient[5];
    int peak = 0;
    for (int i = 0; i < 5; ++i) {
      gradient[i] = std::abs(profile[i + 2] - profile[i]) / 2.0;
      if (gradient[i] > gradient[peak]) peak = i;
    }
    double offset = 10.0;  // the peak two pixels off: a failure
    if (peak >= 1 && peak <= 3) {
      const double gm = gradient[peak - 1], g0 = gradient[peak], gp = gradient[peak + 1];
      const double curvature = gm - 2.0 * g0 + gp;
      offset = (peak - 2) + (curvature < 0.0 ? 0.5 * (gm - gp) / curvature : 0.0);
    }
    ++check->samples;
    check->off += std::abs(offset) > 0.25;
    check->worst = std::max(check->worst, std::abs(offset));
  }
}

void CheckSceneEdges(const char* scene, const SimulationConfig& config, const std::vector<int>& frames) {
  const SimulatedSequence sequence = Simulate(config);
  const SequenceRenderer renderer(sequence, config);
  EdgeCheck check;
  for (const int k : frames) {
    for (int camera = 0; camera < 2; ++camera) {
      const cv::Mat image = renderer.Image(k, camera);
      const StereoFrame& frame = sequence.sequence.frames[k];
      const std::vector<Segment2d> edges = ProjectedEdges(sequence.surfaces, renderer.CamFromWorld(k, camera),
                                                          camera == 0 ? config.rig.left : config.rig.right);
      for (const LineObservation& o : camera == 0 ? frame.left : frame.right) CheckEdge(image, o.segment, edges, &check);
    }
  }
  std::printf("%s: %d samples, %d off, worst %.3f px, %d weak, %d crowded\n", scene, check.samples, check.off,
              check.worst, check.weak, check.crowded);
  EXPECT_GT(check.samples, 1000) << scene;
  EXPECT_EQ(check.off, 0) << scene << ": worst " << check.worst << " px";
}

void CheckSceneEdges(const char* scene) { CheckSceneEdges(scene, SharpConfig(scene, 30), {0, 29}); }

TEST(Rasterizer, RoomEdgesLieOnTheProjectedSegments) { CheckSceneEdges("room"); }
TEST(Rasterizer, CorridorEdgesLieOnTheProjectedSegments) { CheckSceneEdges("corridor"); }
TEST(Rasterizer, PaperEdgesLieOnTheProjectedSegments) { CheckSceneEdges("paper"); }

// The street driven by the car profile: its first frame and the middle of the turn.
SimulationConfig StreetDrive(int frames) {
  SimulationConfig config = SharpConfig("street", frames);
  config.motion.profile = MotionProfile::kCar;
  return config;
}
int MiddleOfTheTurn(const SimulationConfig& config) {
  const Trajectory t = MakeTrajectory(config.motion, config.frames, config.frame_rate, config.MotionSeed());
  for (std::size_t k = 0; k < t.size(); ++k) {
    const Eigen::Vector3d forward = t[k].world_from_cam.rotation.col(2);
    if (std::atan2(forward.x(), forward.z()) >= 0.5 * config.motion.car.turn_deg * M_PI / 180.0) return static_cast<int>(k);
  }
  return -1;
}

TEST(Rasterizer, StreetEdgesLieOnTheProjectedSegments) {
  const SimulationConfig config = StreetDrive(70);
  const int turn = MiddleOfTheTurn(config);
  ASSERT_GT(turn, 0);
  CheckSceneEdges("street", config, {0, turn});
}

}  // namespace
}  // namespace slt

namespace slt {
namespace {

// A square [x0, x1] x [y0, y1] at depth z facing the camera at the origin, flat albedo.
Surface FlatSquare(double x0, double y0, double x1, double y1, double z, double albedo) {
  return MakeSurface({{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}}, -Eigen::Vector3d::UnitZ(),
                     {albedo, 0.0, TexturePattern::kFlat, 0.1, 0});
}

TEST(Rasterizer, AnOccludedSegmentIsNotDrawnNorVisible) {
  // A bright square at 2 m on a wall at 3 m; a dark panel at 1 m hides the left half of the
  // square's top edge (y = -0.2).
  const std::vector<Surface> surfaces = {FlatSquare(-5, -5, 5, 5, 3.0, 0.4), FlatSquare(-0.4, -0.2, 0.4, 0.3, 2.0, 0.9),
                                         FlatSquare(-0.5, -0.5, 0.0, 0.0, 1.0, 0.2)};
  const Line3d top{{-0.4, -0.2, 2.0}, {0.4, -0.2, 2.0}};
  std::vector<Eigen::Vector2d> parts;
  Occluders(surfaces).VisibleParts(Eigen::Vector3d::Zero(), top.p, top.q, &parts);
  // The panel's right side (x = 0 at 1 m) hides x < 0 at 2 m: the left half.
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_NEAR(parts[0][0], 0.5, 1e-8);  // the occluder's 1e-9 m inside margin
  EXPECT_EQ(parts[0][1], 1.0);

  const PinholeCamera camera;
  cv::Mat radiance;
  SurfaceRasterizer(surfaces).Render(camera, 640, 480, Rigid3d::Identity(), &radiance);
  const double v = camera.Project(top.p).y();
  // The vertical step across the edge: none on the hidden half (the panel is uniform there),
  // the full step on the visible half.
  for (const double x : {-0.35, -0.25, -0.15, -0.05, 0.05, 0.15, 0.25, 0.35}) {
    const Eigen::Vector2d u = camera.Project(Eigen::Vector3d(x, -0.2, 2.0));
    const int column = static_cast<int>(std::lround(u.x()));
    const double step = radiance.at<float>(static_cast<int>(v) + 3, column) - radiance.at<float>(static_cast<int>(v) - 3, column);
    if (x < 0.0) {
      EXPECT_EQ(step, 0.0) << x;
    } else {
      EXPECT_GT(step, 0.2) << x;
    }
  }
}

TEST(Rasterizer, TexturedPointsAppearAtTheDisparityOfTheirDepth) {
  // The left image's texture seen from the right camera: a point of depth Z is at disparity
  // fx B / Z in this rectified rig; radiance is view-independent, so the right image holds the
  // same value there (up to interpolation), and a disparity 2 px off does not.
  const SimulationConfig config = SharpConfig("room", 2);
  const SimulatedSequence sequence = Simulate(config);
  const SequenceRenderer renderer(sequence, config);
  cv::Mat left, right, left_ids, right_ids;
  renderer.Rasterizer().Render(config.rig.left, 640, 480, renderer.CamFromWorld(0, 0), &left, &left_ids);
  renderer.Rasterizer().Render(config.rig.right, 640, 480, renderer.CamFromWorld(0, 1), &right, &right_ids);
  const auto bilinear = [](const cv::Mat& m, double x, double y) {
    const int i = static_cast<int>(std::floor(x)), j = static_cast<int>(std::floor(y));
    const double fx = x - i, fy = y - j;
    return (1 - fy) * ((1 - fx) * m.at<float>(j, i) + fx * m.at<float>(j, i + 1)) +
           fy * ((1 - fx) * m.at<float>(j + 1, i) + fx * m.at<float>(j + 1, i + 1));
  };
  double error = 0.0, wrong = 0.0;
  int points = 0;
  for (int y = 20; y < 460; y += 7) {
    for (int x = 60; x < 620; x += 7) {
      const int id = left_ids.at<int>(y, x);
      bool interior = id >= 0;
      for (int dy = -3; dy <= 3 && interior; ++dy) {
        for (int dx = -3; dx <= 3 && interior; ++dx) interior = left_ids.at<int>(y + dy, x + dx) == id;
      }
      if (!interior || sequence.surfaces[id].texture.contrast == 0.0) continue;
      // Depth from the surface's plane: n . (z r) = d in the left camera.
      const Surface& s = sequence.surfaces[id];
      const Eigen::Vector3d ray((x - config.rig.left.cx) / config.rig.left.fx,
                                (y - config.rig.left.cy) / config.rig.left.fy, 1.0);
      const double z = s.normal.dot(s.vertices[0]) / s.normal.dot(ray);  // world = left camera at frame 0
      const double disparity = config.rig.left.fx * config.rig.Baseline() / z;
      const double xr = x - disparity;
      if (xr < 3 || right_ids.at<int>(y, static_cast<int>(std::lround(xr))) != id) continue;
      error += std::abs(bilinear(right, xr, y) - left.at<float>(y, x));
      wrong += std::abs(bilinear(right, xr - 2.0, y) - left.at<float>(y, x));
      ++points;
    }
  }
  ASSERT_GT(points, 500);
  EXPECT_LT(error / points, 0.002);  // radiance units (1 = white)
  EXPECT_GT(wrong / points, 3.0 * error / points);
}

TEST(Rasterizer, StructuredScenesAreClosed) {
  // Every pixel of every image sees a surface: no gaps in the walls, floors or openings.
  for (const char* scene : {"room", "corridor", "street"}) {
    const SimulationConfig config = std::string(scene) == "street" ? StreetDrive(200) : SharpConfig(scene, 100);
    const SimulatedSequence sequence = Simulate(config);
    const SequenceRenderer renderer(sequence, config);
    for (const int k : {0, config.frames / 2, config.frames - 1}) {
      for (int camera = 0; camera < 2; ++camera) {
        cv::Mat radiance, ids;
        renderer.Rasterizer().Render(camera == 0 ? config.rig.left : config.rig.right, config.rig.width,
                                     config.rig.height, renderer.CamFromWorld(k, camera), &radiance, &ids);
        double lowest = 0.0;
        cv::minMaxLoc(ids, &lowest);
        EXPECT_GE(lowest, 0.0) << scene << " frame " << k << " camera " << camera;
      }
    }
  }
}

}  // namespace
}  // namespace slt
