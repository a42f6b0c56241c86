#include "simulator/simulator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "common/json_reader.h"
#include "dataset/stereo_lines_io.h"
#include "simulator/clipping.h"

namespace slt {
namespace {

SimulationConfig FromJson(const char* text) { return SimulationConfigFromJson(nlohmann::json::parse(text), "test"); }

// The image line of a 3-D line in one camera of the true rig at frame k: K^-T (P x Q) with P, Q
// in camera coordinates (valid wherever the endpoints are, even behind the camera).
Eigen::Vector3d ImageLine(const SimulatedSequence& s, std::size_t k, int camera, const Line3d& line) {
  Rigid3d cam_from_world = s.ground_truth[k].world_from_cam.Inverse();
  if (camera == 1) cam_from_world = s.true_rig.right_from_left * cam_from_world;
  const PinholeCamera& intrinsics = camera == 0 ? s.true_rig.left : s.true_rig.right;
  return PixelLineFromNormalizedLine(intrinsics, (cam_from_world * line.p).cross(cam_from_world * line.q));
}

Eigen::Vector2d ProjectEndpoint(const SimulatedSequence& s, std::size_t k, int camera, const Eigen::Vector3d& x) {
  Rigid3d cam_from_world = s.ground_truth[k].world_from_cam.Inverse();
  if (camera == 1) cam_from_world = s.true_rig.right_from_left * cam_from_world;
  return (camera == 0 ? s.true_rig.left : s.true_rig.right).Project(cam_from_world * x);
}

const std::vector<LineObservation>& Image(const StereoFrame& frame, int camera) {
  return camera == 0 ? frame.left : frame.right;
}

bool SameObservations(const SimulatedSequence& a, const SimulatedSequence& b) {
  if (a.sequence.frames.size() != b.sequence.frames.size()) return false;
  for (std::size_t k = 0; k < a.sequence.frames.size(); ++k) {
    for (int camera : {0, 1}) {
      const auto &x = Image(a.sequence.frames[k], camera), &y = Image(b.sequence.frames[k], camera);
      if (x.size() != y.size()) return false;
      for (std::size_t i = 0; i < x.size(); ++i) {
        if (x[i].id != y[i].id || x[i].segment != y[i].segment) return false;
      }
    }
  }
  return true;
}

bool SameSceneAndMotion(const SimulatedSequence& a, const SimulatedSequence& b) {
  if (a.lines.size() != b.lines.size() || a.ground_truth.size() != b.ground_truth.size()) return false;
  for (std::size_t i = 0; i < a.lines.size(); ++i) {
    if (a.lines[i].p != b.lines[i].p || a.lines[i].q != b.lines[i].q) return false;
  }
  for (std::size_t k = 0; k < a.ground_truth.size(); ++k) {
    if (a.ground_truth[k].world_from_cam.ToMatrix4() != b.ground_truth[k].world_from_cam.ToMatrix4()) return false;
  }
  return true;
}

TEST(Simulate, DefaultIsThePaperProtocol) {
  const SimulatedSequence s = Simulate(SimulationConfig{});
  EXPECT_EQ(s.lines.size(), 40u);
  ASSERT_EQ(s.sequence.frames.size(), 100u);
  ASSERT_EQ(s.ground_truth.size(), 100u);
  EXPECT_TRUE(s.ground_truth[0].world_from_cam.ToMatrix4().isIdentity(0.0));
  EXPECT_NEAR(s.true_rig.left.fx, 848.7, 1e-12);
  EXPECT_EQ(s.sequence.rig.left.fx, s.true_rig.left.fx);
  // The idealised protocol observes nearly every line in both images in every frame (a line
  // pointing at the camera can be shorter than min_length_px for a while).
  std::size_t observed = 0;
  for (std::size_t k = 0; k < 100; ++k) {
    EXPECT_EQ(s.sequence.frames[k].time, s.ground_truth[k].time);
    EXPECT_GE(s.sequence.frames[k].left.size(), 38u) << k;
    EXPECT_GE(s.sequence.frames[k].right.size(), 38u) << k;
    observed += s.sequence.frames[k].left.size() + s.sequence.frames[k].right.size();
  }
  EXPECT_GT(observed, 0.99 * 100 * 2 * 40);
}

TEST(Simulate, NoiseFreeObservationsLieOnTheProjectedLines) {
  for (const char* text : {R"({"noise": {"endpoint_px": 0}})",
                           R"({"noise": {"endpoint_px": 0, "endpoints": "sliding"}, "observation": {"clip_to_image": true}})",
                           R"({"noise": {"endpoint_px": 0, "endpoints": "sliding"}, "scene": {"type": "corridor"},
                               "observation": {"clip_to_image": true}})"}) {
    const SimulatedSequence s = Simulate(FromJson(text));
    std::size_t checked = 0;
    for (std::size_t k = 0; k < s.sequence.frames.size(); ++k) {
      for (int camera : {0, 1}) {
        for (const LineObservation& o : Image(s.sequence.frames[k], camera)) {
          const Eigen::Vector3d line = ImageLine(s, k, camera, s.lines[o.id]);
          EXPECT_LT(std::abs(SignedDistance(line, o.segment.head<2>())), 1e-9) << text;
          EXPECT_LT(std::abs(SignedDistance(line, o.segment.tail<2>())), 1e-9) << text;
          ++checked;
        }
      }
    }
    EXPECT_GT(checked, 2000u) << text;
  }
}

TEST(Simulate, FixedEndpointsAreTheProjectedEndpoints) {
  const SimulatedSequence s = Simulate(FromJson(R"({"noise": {"endpoint_px": 0}})"));
  std::size_t checked = 0;
  for (std::size_t k = 0; k < s.sequence.frames.size(); ++k) {
    for (int camera : {0, 1}) {
      for (const LineObservation& o : Image(s.sequence.frames[k], camera)) {
        EXPECT_LT((o.segment.head<2>() - ProjectEndpoint(s, k, camera, s.lines[o.id].p)).norm(), 1e-9);
        EXPECT_LT((o.segment.tail<2>() - ProjectEndpoint(s, k, camera, s.lines[o.id].q)).norm(), 1e-9);
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 7000u);  // 100 frames x 2 images x most of the 40 lines
}

TEST(Simulate, SlidingEndpointsMoveAlongTheLine) {
  SimulationConfig c = FromJson(R"({"noise": {"endpoint_px": 0, "endpoints": "sliding"}, "motion": {"type": "static"}})");
  const SimulatedSequence s = Simulate(c);
  // The camera does not move, yet the observed extents differ from frame to frame and stay
  // within slide_fraction of the 3-D segment's ends.
  std::size_t moved = 0;
  for (std::size_t k = 1; k < s.sequence.frames.size(); ++k) {
    for (std::size_t i = 0; i < s.sequence.frames[k].left.size(); ++i) {
      const LineObservation& o = s.sequence.frames[k].left[i];
      const Eigen::Vector2d p = ProjectEndpoint(s, k, 0, s.lines[o.id].p);
      const Eigen::Vector2d q = ProjectEndpoint(s, k, 0, s.lines[o.id].q);
      if (o.segment != s.sequence.frames[k - 1].left[i].segment) ++moved;
      // Perspective distorts the fraction; 0.25 of the 3-D length is well under 0.5 in the image.
      EXPECT_LT((o.segment.head<2>() - p).norm(), 0.5 * (q - p).norm());
      EXPECT_LT((o.segment.tail<2>() - q).norm(), 0.5 * (q - p).norm());
    }
  }
  EXPECT_EQ(moved, 99u * 40u);
}

TEST(Simulate, UniformNoiseStaysWithinItsBound) {
  SimulationConfig c;
  c.noise.endpoint_px = 0.0;
  const SimulatedSequence clean = Simulate(c);
  c.noise.endpoint_px = 2.5;
  const SimulatedSequence noisy = Simulate(c);
  double largest = 0.0, sum = 0.0;
  std::size_t count = 0;
  for (std::size_t k = 0; k < clean.sequence.frames.size(); ++k) {
    for (int camera : {0, 1}) {
      const auto &x = Image(clean.sequence.frames[k], camera), &y = Image(noisy.sequence.frames[k], camera);
      ASSERT_EQ(x.size(), y.size());
      for (std::size_t i = 0; i < x.size(); ++i) {
        ASSERT_EQ(x[i].id, y[i].id);
        const Eigen::Vector4d d = y[i].segment - x[i].segment;
        largest = std::max(largest, d.cwiseAbs().maxCoeff());
        sum += d.sum();
        count += 4;
      }
    }
  }
  EXPECT_LE(largest, 2.5 + 1e-9);
  EXPECT_GT(largest, 2.45);
  EXPECT_LT(std::abs(sum / count), 0.05);  // zero mean: sigma of the mean is 1.44 / sqrt(32000)
}

TEST(Simulate, GaussianNoiseHasTheConfiguredSigma) {
  SimulationConfig c;
  c.noise.endpoint_px = 0.0;
  const SimulatedSequence clean = Simulate(c);
  c.noise.model = NoiseModel::kGaussian;
  c.noise.endpoint_px = 1.5;
  const SimulatedSequence noisy = Simulate(c);
  double sum = 0.0, sum_squares = 0.0;
  std::size_t count = 0;
  for (std::size_t k = 0; k < clean.sequence.frames.size(); ++k) {
    const auto &x = clean.sequence.frames[k].left, &y = noisy.sequence.frames[k].left;
    ASSERT_EQ(x.size(), y.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      ASSERT_EQ(x[i].id, y[i].id);
      const Eigen::Vector4d d = y[i].segment - x[i].segment;
      sum += d.sum();
      sum_squares += d.squaredNorm();
      count += 4;
    }
  }
  const double mean = sum / count, sigma = std::sqrt(sum_squares / count - mean * mean);
  EXPECT_LT(std::abs(mean), 0.05);
  EXPECT_NEAR(sigma, 1.5, 0.05);  // 16000 samples: the estimate's sigma is 0.008
}

TEST(Simulate, SameConfigGivesBitIdenticalOutput) {
  const SimulationConfig c = FromJson(R"({"seed": 77, "outliers": {"rate": 0.1}, "noise": {"endpoints": "sliding"}})");
  const SimulatedSequence a = Simulate(c), b = Simulate(c);
  EXPECT_TRUE(SameSceneAndMotion(a, b));
  EXPECT_TRUE(SameObservations(a, b));
  SimulationConfig other = c;
  other.seed = 78;
  EXPECT_FALSE(SameSceneAndMotion(a, Simulate(other)));
}

TEST(Simulate, StreamsAreIndependent) {
  SimulationConfig c;
  c.seed = 3;
  c.noise.endpoint_px = 0.0;
  const SimulatedSequence clean = Simulate(c);
  // A noise sweep: same scene and motion; the offsets are one draw scaled by the level.
  c.noise.endpoint_px = 1.0;
  const SimulatedSequence one = Simulate(c);
  c.noise.endpoint_px = 2.5;
  const SimulatedSequence two_and_half = Simulate(c);
  EXPECT_TRUE(SameSceneAndMotion(clean, one));
  EXPECT_TRUE(SameSceneAndMotion(clean, two_and_half));
  for (std::size_t k = 0; k < clean.sequence.frames.size(); ++k) {
    const auto &x = clean.sequence.frames[k].left, &y = one.sequence.frames[k].left,
               &z = two_and_half.sequence.frames[k].left;
    ASSERT_EQ(x.size(), z.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      EXPECT_LT((z[i].segment - x[i].segment - 2.5 * (y[i].segment - x[i].segment)).norm(), 1e-9);
    }
  }
  // Other noise seed: other noise, same scene and motion, same noise-free projections.
  c.seeds.noise = 1000;
  const SimulatedSequence reseeded = Simulate(c);
  EXPECT_TRUE(SameSceneAndMotion(clean, reseeded));
  EXPECT_FALSE(SameObservations(two_and_half, reseeded));
  c.noise.endpoint_px = 0.0;
  EXPECT_TRUE(SameObservations(clean, Simulate(c)));
  // Other scene seed: other lines, same motion.
  c.seeds.scene = 1000;
  const SimulatedSequence other_scene = Simulate(c);
  EXPECT_NE(other_scene.lines[0].p, clean.lines[0].p);
  EXPECT_EQ(other_scene.ground_truth.back().world_from_cam.ToMatrix4(),
            clean.ground_truth.back().world_from_cam.ToMatrix4());
  // Other motion seed: same lines, other motion.
  c.seeds.scene.reset();
  c.seeds.motion = 1000;
  const SimulatedSequence other_motion = Simulate(c);
  EXPECT_EQ(other_motion.lines[0].p, clean.lines[0].p);
  EXPECT_NE(other_motion.ground_truth.back().world_from_cam.ToMatrix4(),
            clean.ground_truth.back().world_from_cam.ToMatrix4());
}

TEST(Simulate, EndpointModelsShareTheNoise) {
  // The offsets added to the endpoints do not depend on the endpoint model either.
  std::vector<Eigen::Vector4d> offsets[2];
  for (EndpointModel model : {EndpointModel::kFixed, EndpointModel::kSliding}) {
    SimulationConfig c;
    c.noise.endpoints = model;
    c.noise.endpoint_px = 0.0;
    const SimulatedSequence clean = Simulate(c);
    c.noise.endpoint_px = 2.0;
    const SimulatedSequence noisy = Simulate(c);
    for (std::size_t k = 0; k < clean.sequence.frames.size(); ++k) {
      const auto &x = clean.sequence.frames[k].right, &y = noisy.sequence.frames[k].right;
      ASSERT_EQ(x.size(), 40u);
      ASSERT_EQ(y.size(), 40u);
      for (std::size_t i = 0; i < x.size(); ++i) {
        offsets[model == EndpointModel::kSliding].push_back(y[i].segment - x[i].segment);
      }
    }
  }
  ASSERT_EQ(offsets[0].size(), offsets[1].size());
  for (std::size_t i = 0; i < offsets[0].size(); ++i) EXPECT_LT((offsets[0][i] - offsets[1][i]).norm(), 1e-9);
}

TEST(Simulate, FocalErrorChangesOnlyTheTrackersRig) {
  SimulationConfig c;
  const SimulatedSequence exact = Simulate(c);
  c.focal_error_px = 200.0;
  const SimulatedSequence wrong = Simulate(c);
  EXPECT_EQ(wrong.sequence.rig.left.fx, exact.true_rig.left.fx + 200.0);
  EXPECT_EQ(wrong.sequence.rig.right.fy, exact.true_rig.right.fy + 200.0);
  EXPECT_EQ(wrong.sequence.rig.left.cx, exact.true_rig.left.cx);
  EXPECT_EQ(wrong.true_rig.left.fx, exact.true_rig.left.fx);
  EXPECT_TRUE(SameSceneAndMotion(exact, wrong));
  EXPECT_TRUE(SameObservations(exact, wrong));
}

TEST(Simulate, ClippingKeepsSegmentsInsideTheImage) {
  SimulationConfig c = FromJson(R"({"motion": {"sinusoid": {"max_rotation_deg": 3}}})");
  std::size_t outside = 0;
  for (const StereoFrame& frame : Simulate(c).sequence.frames) {
    for (const LineObservation& o : frame.left) {
      outside += !c.rig.InImage(o.segment.head<2>()) || !c.rig.InImage(o.segment.tail<2>());
    }
  }
  EXPECT_GT(outside, 100u);  // without clipping, many are not
  c.observation.clip_to_image = true;
  std::size_t total = 0;
  for (const StereoFrame& frame : Simulate(c).sequence.frames) {
    for (int camera : {0, 1}) {
      for (const LineObservation& o : Image(frame, camera)) {
        EXPECT_TRUE(c.rig.InImage(o.segment.head<2>()) && c.rig.InImage(o.segment.tail<2>()));
        ++total;
      }
    }
  }
  EXPECT_GT(total, 4000u);
}

TEST(Simulate, LinesBehindTheCameraAreNotObserved) {
  for (bool clip : {false, true}) {
    SimulationConfig c;
    c.scene.paper.box_center_m = Eigen::Vector3d(0.0, 0.0, -1.0);
    c.observation.clip_to_image = clip;
    for (const StereoFrame& frame : Simulate(c).sequence.frames) {
      EXPECT_TRUE(frame.left.empty() && frame.right.empty());
    }
  }
}

TEST(Simulate, OutlierRateIsRespected) {
  SimulationConfig c;
  c.noise.endpoint_px = 0.0;
  const SimulatedSequence clean = Simulate(c);
  for (double rate : {0.05, 0.3, 1.0}) {
    c.outliers.rate = rate;
    const SimulatedSequence s = Simulate(c);
    EXPECT_TRUE(SameSceneAndMotion(clean, s));
    std::size_t replaced = 0, total = 0, replaced_first = 0;
    for (std::size_t k = 0; k < s.sequence.frames.size(); ++k) {
      for (int camera : {0, 1}) {
        const auto &x = Image(clean.sequence.frames[k], camera), &y = Image(s.sequence.frames[k], camera);
        ASSERT_EQ(x.size(), y.size());
        for (std::size_t i = 0; i < x.size(); ++i) {
          ASSERT_EQ(x[i].id, y[i].id);
          const bool changed = x[i].segment != y[i].segment;
          replaced += changed;
          replaced_first += changed && k == 0;
          EXPECT_GE((y[i].segment.head<2>() - y[i].segment.tail<2>()).norm(), c.observation.min_length_px);
          ++total;
        }
      }
    }
    // Binomial: within 5 standard deviations.
    const double n = static_cast<double>(total);
    EXPECT_NEAR(replaced / n, rate, 5.0 * std::sqrt(rate * (1.0 - rate) / n) + 1e-12) << rate;
    EXPECT_GT(replaced_first, 0u) << rate;  // the reference frame gets outliers too
  }
}

TEST(Simulate, MaxFeaturesKeepsTheFirstIds) {
  SimulationConfig c = FromJson(R"({"scene": {"type": "room"}, "observation": {"clip_to_image": true}})");
  const SimulatedSequence all = Simulate(c);
  c.max_features = 30;
  const SimulatedSequence some = Simulate(c);
  ASSERT_EQ(some.lines.size(), 30u);
  for (std::size_t k = 0; k < all.sequence.frames.size(); ++k) {
    for (int camera : {0, 1}) {
      std::vector<LineObservation> expected;
      for (const LineObservation& o : Image(all.sequence.frames[k], camera)) {
        if (o.id < 30) expected.push_back(o);
      }
      const auto& got = Image(some.sequence.frames[k], camera);
      ASSERT_EQ(got.size(), expected.size());
      for (std::size_t i = 0; i < got.size(); ++i) {
        EXPECT_EQ(got[i].id, expected[i].id);
        EXPECT_EQ(got[i].segment, expected[i].segment);
      }
    }
  }
}

// The structured scenes with their default motions and clipping on: enough lines in every
// frame of both images, and lines entering and leaving the view.
void CheckStructuredVisibility(const char* scene) {
  for (std::uint64_t seed : {1, 2, 3}) {
    const nlohmann::json j = {
        {"seed", seed}, {"scene", {{"type", scene}}}, {"observation", {{"clip_to_image", true}}}};
    const SimulationConfig c = SimulationConfigFromJson(j, "test");
    const SimulatedSequence s = Simulate(c);
    std::set<std::int64_t> first, ever;
    std::size_t left_view = 0;  // frames missing some line seen in the first frame
    for (std::size_t k = 0; k < s.sequence.frames.size(); ++k) {
      const StereoFrame& f = s.sequence.frames[k];
      std::set<std::int64_t> left, both;
      for (const LineObservation& o : f.left) left.insert(o.id);
      for (const LineObservation& o : f.right) {
        if (left.count(o.id)) both.insert(o.id);
      }
      EXPECT_GE(f.left.size(), 15u) << scene << " frame " << k;
      EXPECT_GE(f.right.size(), 15u) << scene << " frame " << k;
      EXPECT_GE(both.size(), 15u) << scene << " frame " << k;
      if (k == 0) first = both;
      left_view += std::any_of(first.begin(), first.end(), [&](std::int64_t id) { return !both.count(id); });
      ever.insert(both.begin(), both.end());
    }
    EXPECT_GT(left_view, 0u) << scene;
    EXPECT_GT(ever.size(), first.size()) << scene;  // lines entered the view
  }
}

TEST(Simulate, RoomKeepsLinesInView) { CheckStructuredVisibility("room"); }
TEST(Simulate, CorridorKeepsLinesInView) { CheckStructuredVisibility("corridor"); }

TEST(Simulate, PaperSceneStaysMostlyInView) {
  // The paper protocol does not clip (its lines are infinite), but the lines should mostly be
  // where the cameras see them: crossing the image over 20 px or more.
  std::size_t in_view = 0, total = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    SimulationConfig c;
    c.seed = seed;
    c.noise.endpoint_px = 0.0;
    for (const StereoFrame& frame : Simulate(c).sequence.frames) {
      for (int camera : {0, 1}) {
        for (const LineObservation& o : Image(frame, camera)) {
          Eigen::Vector2d a = o.segment.head<2>(), b = o.segment.tail<2>();
          in_view += ClipSegmentToImage(c.rig.width, c.rig.height, &a, &b) && (a - b).norm() >= 20.0;
          ++total;
        }
      }
    }
  }
  EXPECT_GT(static_cast<double>(in_view) / total, 0.9);
}

TEST(Simulate, OutputSatisfiesTheStereoLinesRules) {
  // Whatever the options, the sequence is one that WriteStereoLines accepts and
  // ReadStereoLines reads back (finite values, ordered times, non-degenerate segments, ids
  // unique per image).
  for (const char* text :
       {"{}", R"({"scene": {"type": "room"}, "outliers": {"rate": 0.3}, "noise": {"model": "gaussian"}})",
        R"({"scene": {"type": "corridor"}, "noise": {"endpoints": "sliding"}, "focal_error_px": 100})",
        R"({"motion": {"type": "pure_rotation"}, "observation": {"min_length_px": 0}})"}) {
    EXPECT_NO_THROW(CheckStereoSequence(Simulate(FromJson(text)).sequence, text));
  }
}

TEST(Simulate, ShortSegmentsAreDropped) {
  SimulationConfig c;
  c.noise.endpoint_px = 0.0;
  const std::size_t all = Simulate(c).sequence.frames[0].left.size();
  c.observation.min_length_px = 150.0;
  const SimulatedSequence s = Simulate(c);
  EXPECT_LT(s.sequence.frames[0].left.size(), all);
  for (const StereoFrame& frame : s.sequence.frames) {
    for (const LineObservation& o : frame.left) {
      EXPECT_GE((o.segment.head<2>() - o.segment.tail<2>()).norm(), 150.0);
    }
  }
}

}  // namespace
}  // namespace slt
