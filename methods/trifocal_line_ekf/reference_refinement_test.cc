#include "methods/trifocal_line_ekf/reference_refinement.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include "evaluation/consistency.h"
#include "common/random.h"
#include "geometry/se3.h"
#include "methods/trifocal_line_ekf/line_transfer_model.h"
#include "methods/trifocal_line_ekf/trifocal_line_ekf.h"
#include "simulator/simulator.h"

namespace slt {
namespace {

// Lines 2-3 m ahead of the reference camera; the last one horizontal along the baseline, which
// the stereo pair does not define.
const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> kLines = {
    {{-0.6, -0.5, 2.5}, {-0.6, 0.5, 2.5}},  {{0.7, -0.4, 3.0}, {0.7, 0.6, 3.0}},
    {{-0.5, 0.4, 2.0}, {-0.5, 0.4, 3.2}},   {{0.5, -0.45, 2.2}, {0.5, -0.45, 3.4}},
    {{-0.3, -0.3, 2.4}, {0.4, 0.3, 2.8}},   {{0.2, 0.5, 2.6}, {-0.4, -0.2, 2.3}},
    {{-0.5, -0.35, 2.7}, {0.5, -0.35, 2.7}},
};
constexpr int kDegenerate = 6;

PlueckerLine TrueLine(int i) {
  PlueckerLine line;
  line.direction = (kLines[i].second - kLines[i].first).normalized();
  line.moment = kLines[i].first.cross(line.direction);
  return line;
}

struct Seen {
  Segment2d left, right;
  Eigen::Vector3d left_line;  // normalised
};

Seen Observe(const StereoRig& rig, const Rigid3d& cam_from_ref, int i) {
  const Rigid3d right_from_ref = rig.right_from_left * cam_from_ref;
  const auto& [p, q] = kLines[i];
  Seen s;
  s.left << rig.left.Project(cam_from_ref * p), rig.left.Project(cam_from_ref * q);
  s.right << rig.right.Project(right_from_ref * p), rig.right.Project(right_from_ref * q);
  s.left_line = (rig.left.K().transpose() * LineFromSegment(s.left)).normalized();
  return s;
}

Rigid3d KeyframePose(int k) {
  // Walking forward and a little sideways and up, turning slightly.
  Vector6d xi;
  xi << -0.02 * k, -0.01 * k, -0.12 * k, 0.004 * k, 0.01 * k, 0.0;
  return ExpSE3(xi);
}

double LineError(const PlueckerLine& estimate, const PlueckerLine& truth) {
  const double sign = estimate.direction.dot(truth.direction) < 0.0 ? -1.0 : 1.0;
  return (sign * estimate.direction - truth.direction).norm() + (sign * estimate.moment - truth.moment).norm();
}

TEST(ReferenceRefinerTest, RecoversLinesAndPoseFromPerturbedStartAndTriangulatesTheDegenerateLine) {
  StereoRig rig;
  ReferenceRefinementOptions options;
  options.enabled = true;
  options.keyframe_interval = 1;
  options.min_triangulation_angle_deg = 2.0;
  ReferenceRefiner refiner(options, 1.0);
  refiner.Reset(rig);
  refiner.StartReference(static_cast<int>(kLines.size()));
  double start_error = 0.0;
  for (int i = 0; i < static_cast<int>(kLines.size()); ++i) {
    const Seen s = Observe(rig, Rigid3d(), i);
    // A stereo-like error: the line tilted and shifted a little.
    PlueckerLine start = TrueLine(i);
    const Rigid3d tilt = ExpSE3((Vector6d() << 0.01, -0.02, 0.03, 0.01, 0.005, -0.01).finished());
    start = TransformPluecker(tilt, start);
    start_error += LineError(start, TrueLine(i));
    refiner.SetLine(i, start, i != kDegenerate, s.left, s.right, s.left_line);
  }
  Rigid3d newest;
  bool solved = false;
  for (int k = 1; k <= 4; ++k) {
    ASSERT_TRUE(refiner.CountFrame(KeyframePose(k)));
    std::vector<ReferenceRefiner::Observation> observations;
    for (int i = 0; i < static_cast<int>(kLines.size()); ++i) {
      const Seen s = Observe(rig, KeyframePose(k), i);
      observations.push_back({i, s.left, s.right, s.left_line});
    }
    const Rigid3d guess = ExpSE3((Vector6d() << 0.01, -0.01, 0.005, 0.002, 0.0, -0.003).finished()) * KeyframePose(k);
    solved = refiner.AddKeyframeAndSolve(guess, observations, &newest);
    ASSERT_TRUE(solved) << "keyframe " << k;
  }
  // Noise-free segments: the structure and the newest pose are recovered.
  EXPECT_LT(LogSE3(newest * KeyframePose(4).Inverse()).norm(), 1e-6);
  double end_error = 0.0;
  for (int i = 0; i < static_cast<int>(kLines.size()); ++i) {
    ASSERT_TRUE(refiner.Refined(i)) << "line " << i;
    EXPECT_LT(LineError(refiner.Line(i), TrueLine(i)), 1e-6) << "line " << i;
    end_error += LineError(refiner.Line(i), TrueLine(i));
    EXPECT_TRUE(refiner.Covariance(i).allFinite());
    EXPECT_GT(refiner.Covariance(i).determinant(), 0.0);
  }
  EXPECT_GT(start_error, 1e-2);
  EXPECT_LT(end_error, 1e-4 * start_error);
}

// A reference pair at the identity with the true lines (the degenerate one not usable).
void StartAtTheTrueLines(const StereoRig& rig, ReferenceRefiner* refiner) {
  refiner->Reset(rig);
  refiner->StartReference(static_cast<int>(kLines.size()));
  for (int i = 0; i < static_cast<int>(kLines.size()); ++i) {
    const Seen s = Observe(rig, Rigid3d(), i);
    refiner->SetLine(i, TrueLine(i), i != kDegenerate, s.left, s.right, s.left_line);
  }
}

// Four keyframes (KeyframePose(1..4)) of every line, the degenerate one's segments moved up in
// odd keyframes and down in even ones by jitter_px (no 3-D line fits them then); returns the
// refined newest pose.
Rigid3d AddFourKeyframes(const StereoRig& rig, double jitter_px, ReferenceRefiner* refiner) {
  Rigid3d newest;
  for (int k = 1; k <= 4; ++k) {
    EXPECT_TRUE(refiner->CountFrame(KeyframePose(k)));
    std::vector<ReferenceRefiner::Observation> observations;
    for (int i = 0; i < static_cast<int>(kLines.size()); ++i) {
      Seen s = Observe(rig, KeyframePose(k), i);
      if (i == kDegenerate && jitter_px != 0.0) {
        const double shift = (k % 2 == 1 ? 1.0 : -1.0) * jitter_px;
        for (int v : {1, 3}) {
          s.left(v) += shift;
          s.right(v) += shift;
        }
        s.left_line = (rig.left.K().transpose() * LineFromSegment(s.left)).normalized();
      }
      observations.push_back({i, s.left, s.right, s.left_line});
    }
    EXPECT_TRUE(refiner->AddKeyframeAndSolve(KeyframePose(k), observations, &newest));
  }
  return newest;
}

// The options of the noise-draw tests: the endpoints' residual (exact for Gaussian noise), a
// Huber threshold out of reach, a keyframe every frame.
ReferenceRefinementOptions NoiseDrawOptions(PoseCovarianceSource pose_covariance) {
  ReferenceRefinementOptions options;
  options.enabled = true;
  options.keyframe_interval = 1;
  options.segment_residual = SegmentResidual::kEndpoints;
  options.huber_sigma = 1e3;
  options.pose_covariance = pose_covariance;
  return options;
}

// One draw: the reference pair's endpoints with Gaussian noise of sigma reference_px, then
// `keyframes` keyframes with keyframe_px, a solve after each. Returns the newest refined pose.
Rigid3d SolveNoiseDraw(const StereoRig& rig, int keyframes, double reference_px, double keyframe_px, std::mt19937* rng,
                       ReferenceRefiner* refiner) {
  std::normal_distribution<double> pixel_noise(0.0, 1.0);
  auto noisy = [&](const Rigid3d& cam_from_ref, int i, double sigma_px) {
    Seen s = Observe(rig, cam_from_ref, i);
    for (int v = 0; v < 4; ++v) {
      s.left(v) += sigma_px * pixel_noise(*rng);
      s.right(v) += sigma_px * pixel_noise(*rng);
    }
    s.left_line = (rig.left.K().transpose() * LineFromSegment(s.left)).normalized();
    return s;
  };
  refiner->Reset(rig);
  refiner->StartReference(static_cast<int>(kLines.size()));
  for (int i = 0; i < static_cast<int>(kLines.size()); ++i) {
    const Seen s = noisy(Rigid3d(), i, reference_px);
    refiner->SetLine(i, TrueLine(i), i != kDegenerate, s.left, s.right, s.left_line);
  }
  Rigid3d newest;
  for (int k = 1; k <= keyframes; ++k) {
    EXPECT_TRUE(refiner->CountFrame(KeyframePose(k)));
    std::vector<ReferenceRefiner::Observation> observations;
    for (int i = 0; i < static_cast<int>(kLines.size()); ++i) {
      const Seen s = noisy(KeyframePose(k), i, keyframe_px);
      observations.push_back({i, s.left, s.right, s.left_line});
    }
    EXPECT_TRUE(refiner->AddKeyframeAndSolve(KeyframePose(k), observations, &newest));
  }
  return newest;
}

TEST(ReferenceRefinerTest, NewestKeyframeCovarianceDescribesItsErrorOverNoiseDraws) {
  // Endpoints with Gaussian noise of the endpoint sigma in every image (the reference pair's
  // and four keyframes'): the reported marginal covariance of the newest keyframe's pose (the
  // lines' uncertainty and correlations included) must describe the spread of its error. Mean
  // NEES over 300 draws, 6 if consistent: 95 % of such means fall in [5.6, 6.4].
  StereoRig rig;
  // The marginal is computed only when used.
  const ReferenceRefinementOptions options = NoiseDrawOptions(PoseCovarianceSource::kSolve);
  std::mt19937 rng(11);
  const int draws = 300;
  double nees_sum = 0.0;
  for (int draw = 0; draw < draws; ++draw) {
    ReferenceRefiner refiner(options, 1.0);
    const Rigid3d newest = SolveNoiseDraw(rig, 4, 1.0, 1.0, &rng, &refiner);
    Matrix6d covariance;
    ASSERT_TRUE(refiner.NewestPoseCovariance(&covariance));
    // true = Exp(d) estimate (PoseManifold's and the filter's left perturbation).
    const Vector6d d = LogSE3(KeyframePose(4) * newest.Inverse());
    nees_sum += d.dot(covariance.ldlt().solve(d));
  }
  const double nees = nees_sum / draws;
  std::printf("newest keyframe pose: mean NEES %.2f over %d draws\n", nees, draws);
  EXPECT_GT(nees, 5.0);
  EXPECT_LT(nees, 7.0);
}

TEST(ReferenceRefinerTest, ReferencePlacementCovarianceDescribesWhatExactKeyframesLeave) {
  // Gaussian endpoint noise of the endpoint sigma in the reference pair only, sixteen exact
  // keyframes: the keyframes fix the lines' shape and their own poses relative to the lines, so
  // the newest keyframe's error is the reference pair's placement relative to its lines, moved
  // into the newest camera: d = Ad(cam_from_ref) delta, delta ~ N(0, ReferencePlacementCovariance).
  // Mean NEES over 300 draws, 6 if it describes that error exactly (95 % of such means in
  // [5.6, 6.4]); somewhat more, as the keyframes, weighted like the reference, still let the
  // lines bend toward its noise (the fewer keyframes, the more: about 6.7 with eight). And it
  // is part of the newest keyframe's whole marginal (noise in every image): the difference of
  // the two, at the truth, is positive semi-definite.
  StereoRig rig;
  const ReferenceRefinementOptions options = NoiseDrawOptions(PoseCovarianceSource::kReportPlacement);
  std::mt19937 rng(12);
  const int draws = 300;
  const int keyframes = 16;
  double nees_sum = 0.0;
  for (int draw = 0; draw < draws; ++draw) {
    ReferenceRefiner refiner(options, 1.0);
    const Rigid3d newest = SolveNoiseDraw(rig, keyframes, 1.0, 0.0, &rng, &refiner);
    Matrix6d placement;
    ASSERT_TRUE(refiner.ReferencePlacementCovariance(&placement));
    Matrix6d unused;
    EXPECT_FALSE(refiner.NewestPoseCovariance(&unused));  // not computed for this source
    const Matrix6d ad = Adjoint(newest);
    const Matrix6d placement_at_newest = ad * placement * ad.transpose();
    const Vector6d d = LogSE3(KeyframePose(keyframes) * newest.Inverse());
    nees_sum += d.dot(placement_at_newest.ldlt().solve(d));
  }
  const double nees = nees_sum / draws;
  std::printf("newest keyframe pose against the reference placement: mean NEES %.2f over %d draws\n", nees, draws);
  EXPECT_GT(nees, 5.0);
  EXPECT_LT(nees, 7.5);

  ReferenceRefiner exact_placement(options, 1.0), exact_marginal(NoiseDrawOptions(PoseCovarianceSource::kSolve), 1.0);
  const Rigid3d truth = SolveNoiseDraw(rig, keyframes, 0.0, 0.0, &rng, &exact_placement);
  SolveNoiseDraw(rig, keyframes, 0.0, 0.0, &rng, &exact_marginal);
  Matrix6d placement, marginal;
  ASSERT_TRUE(exact_placement.ReferencePlacementCovariance(&placement));
  ASSERT_TRUE(exact_marginal.NewestPoseCovariance(&marginal));
  const Matrix6d ad = Adjoint(truth);
  const Eigen::SelfAdjointEigenSolver<Matrix6d> rest(marginal - ad * placement * ad.transpose());
  EXPECT_GT(rest.eigenvalues().minCoeff(), -1e-9 * marginal.norm());
  EXPECT_GT(rest.eigenvalues().maxCoeff(), 0.1 * marginal.norm());  // the keyframes' own noise adds
}

// The refined lines' covariances after four noise-free keyframes, with the given residual, in
// the ambient [n; d] (the tangent's basis depends on the solve's path).
std::vector<Matrix6d> RefinedCovariances(SegmentResidual residual) {
  StereoRig rig;
  ReferenceRefinementOptions options;
  options.enabled = true;
  options.keyframe_interval = 1;
  options.segment_residual = residual;
  ReferenceRefiner refiner(options, 1.0);
  StartAtTheTrueLines(rig, &refiner);
  const Rigid3d newest = AddFourKeyframes(rig, 0.0, &refiner);
  EXPECT_LT(LogSE3(newest * KeyframePose(4).Inverse()).norm(), 1e-9);
  std::vector<Matrix6d> covariances;
  for (int i = 0; i < static_cast<int>(kLines.size()); ++i) {
    if (i == kDegenerate) continue;
    EXPECT_TRUE(refiner.Refined(i)) << "line " << i;
    EXPECT_LT(LineError(refiner.Line(i), TrueLine(i)), 1e-9) << "line " << i;
    const Eigen::Matrix<double, 6, 4> basis = refiner.TangentBasis(i);
    covariances.push_back(basis * refiner.Covariance(i) * basis.transpose());
  }
  return covariances;
}

TEST(ReferenceRefinerTest, EndpointResidualWeighsTheLinesTiltAsTheEndpointsMeasureIt) {
  // Taylor's residual (sigma / sqrt(2)) and the endpoints' (sigma) carry the same information on
  // a line's offset across its segments, and the endpoints' three times Taylor's on its tilt
  // about their middles: every refined line's covariance is smaller, never larger.
  const std::vector<Matrix6d> taylor = RefinedCovariances(SegmentResidual::kTaylor);
  const std::vector<Matrix6d> endpoints = RefinedCovariances(SegmentResidual::kEndpoints);
  ASSERT_EQ(taylor.size(), endpoints.size());
  for (size_t i = 0; i < taylor.size(); ++i) {
    const Matrix6d difference = taylor[i] - endpoints[i];
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix6d>(difference).eigenvalues().minCoeff(), -1e-9 * taylor[i].norm())
        << "line " << i;
    EXPECT_LT(endpoints[i].trace(), 0.9 * taylor[i].trace()) << "line " << i;
  }
}

// The consistency gate of the lines triangulated from keyframes: the degenerate line reaches
// the filter (Refined) only when its segments fit and its position is determined.
bool DegenerateLinePassesGate(double max_sigma_m, double jitter_px) {
  StereoRig rig;
  ReferenceRefinementOptions options;
  options.enabled = true;
  options.keyframe_interval = 1;
  options.min_triangulation_angle_deg = 2.0;
  options.triangulated_max_sigma_m = max_sigma_m;
  options.triangulated_gate_probability = 0.99;
  ReferenceRefiner refiner(options, 1.0);
  StartAtTheTrueLines(rig, &refiner);
  AddFourKeyframes(rig, jitter_px, &refiner);
  for (int i = 0; i < static_cast<int>(kLines.size()); ++i) {
    if (i != kDegenerate) {
      EXPECT_TRUE(refiner.Refined(i)) << "line " << i;
    }
  }
  return refiner.Refined(kDegenerate);
}

TEST(ReferenceRefinerTest, TriangulatedLineReachesTheFilterOnlyThroughTheConsistencyGate) {
  EXPECT_TRUE(DegenerateLinePassesGate(1.0, 0.0));
  EXPECT_FALSE(DegenerateLinePassesGate(1e-6, 0.0));  // position not determined to 1 um
  EXPECT_FALSE(DegenerateLinePassesGate(1.0, 8.0));   // segments inconsistent by 8 px
}

TEST(ReferenceRefinerTest, KeyframesEveryIntervalFrames) {
  ReferenceRefinementOptions options;
  options.keyframe_interval = 3;
  ReferenceRefiner refiner(options, 1.0);
  refiner.Reset(StereoRig());
  refiner.StartReference(0);
  std::vector<bool> keyframes;
  for (int f = 0; f < 7; ++f) keyframes.push_back(refiner.CountFrame(Rigid3d()));
  EXPECT_EQ(keyframes, (std::vector<bool>{false, false, true, false, false, true, false}));
}

TEST(ReferenceRefinerTest, KeyframesWaitForTheMinimumDistanceFromTheLastOne) {
  // 1 cm per frame along x, a keyframe at least every 2 frames and 2.5 cm from the last one
  // (the reference pair at the origin for the first).
  ReferenceRefinementOptions options;
  options.keyframe_interval = 2;
  options.keyframe_min_distance_m = 0.025;
  ReferenceRefiner refiner(options, 1.0);
  refiner.Reset(StereoRig());
  refiner.StartReference(0);
  std::vector<int> keyframes;
  for (int f = 1; f <= 8; ++f) {
    Rigid3d cam_from_ref;
    cam_from_ref.translation = Eigen::Vector3d(-0.01 * f, 0.0, 0.0);
    if (!refiner.CountFrame(cam_from_ref)) continue;
    keyframes.push_back(f);
    Rigid3d newest;
    refiner.AddKeyframeAndSolve(cam_from_ref, {}, &newest);  // no lines: stored, not solved
  }
  EXPECT_EQ(keyframes, (std::vector<int>{3, 6}));
}

TEST(ReferenceRefinerTest, RefinementNeedsTheReferenceToCurrentDirectionAndPropagatedNoise) {
  LineTransferOptions options;
  options.refinement.enabled = true;
  EXPECT_NO_THROW(options.Check());
  options.direction = TransferDirection::kCurrentToReference;
  EXPECT_THROW(options.Check(), std::exception);
  options.direction = TransferDirection::kReferenceToCurrent;
  options.noise = MeasurementNoise::kFixed;
  EXPECT_THROW(options.Check(), std::exception);
  options.refinement.enabled = false;
  EXPECT_NO_THROW(options.Check());
  options.refinement.keyframe_interval = 0;
  EXPECT_THROW(options.Check(), std::exception);
}

// The tracker with the refinement over a sequence: every pose and covariance, in order.
// `refinement` adds to {"enabled": true}.
std::vector<TrackerOutput> TrackWithRefinement(const StereoSequence& sequence, const nlohmann::json& refinement) {
  nlohmann::json options = {{"measurement", {{"refinement", {{"enabled", true}}}}}};
  options["measurement"]["refinement"].update(refinement);
  std::unique_ptr<PoseTracker> tracker = TrifocalLineEkfInfo().create(options, "test");
  tracker->Reset(sequence.rig);
  std::vector<TrackerOutput> outputs;
  for (const StereoFrame& frame : sequence.frames) outputs.push_back(tracker->Track(frame));
  return outputs;
}

bool BitwiseEqual(const TrackerOutput& a, const TrackerOutput& b) {
  return std::memcmp(a.cam_from_world.rotation.data(), b.cam_from_world.rotation.data(), 9 * sizeof(double)) == 0 &&
         std::memcmp(a.cam_from_world.translation.data(), b.cam_from_world.translation.data(), 3 * sizeof(double)) == 0 &&
         std::memcmp(a.covariance.data(), b.covariance.data(), 36 * sizeof(double)) == 0 && a.status == b.status;
}

// The first `frames` frames of the room loop of experiments/configs/long_room.json.
SimulatedSequence RoomLoopStart(int frames, std::uint64_t seed = 3) {
  return Simulate(SimulationConfigFromJson(
      {{"frames", frames},
       {"seed", seed},
       {"scene", {{"type", "room"}}},
       {"motion", {{"type", "loop"}, {"loop", {{"radius_x_m", 0.2}, {"radius_z_m", 0.28}}}}},
       {"observation", {{"clip_to_image", true}}},
       {"noise", {{"endpoint_px", 1.0}}}},
      "test"));
}

TEST(ReferenceRefinerTest, RoomLoopIsBitwiseRepeatableWhateverTheHeapAndThread) {
  // The room loop of experiments/configs/long_room.json, shortened: 25 keyframes, so the window
  // (8 keyframes here) drops some. A second run on another thread (another malloc arena) with the
  // heap first shuffled (blocks of every small size freed in a random order, so that new
  // allocations land in a different address order) must give the same bits: nothing in the
  // refinement may depend on addresses (Ceres orders each elimination group by pointer),
  // uninitialised memory or threads.
  const SimulatedSequence sim = RoomLoopStart(250);
  // 8 keyframes: over 250 frames the window is full and drops keyframes.
  const nlohmann::json refinement = {{"max_keyframes", 8}};
  const std::vector<TrackerOutput> first = TrackWithRefinement(sim.sequence, refinement);

  std::vector<TrackerOutput> second;
  std::thread([&] {
    std::mt19937 random(7);
    std::vector<std::unique_ptr<char[]>> blocks, guards;
    for (int i = 0; i < 4000; ++i) {
      blocks.emplace_back(new char[16 + random() % 1024]);
      guards.emplace_back(new char[24]);  // keeps freed neighbours from merging
    }
    std::shuffle(blocks.begin(), blocks.end(), random);
    blocks.resize(blocks.size() / 2);
    second = TrackWithRefinement(sim.sequence, refinement);
  }).join();

  ASSERT_EQ(first.size(), second.size());
  int differing = 0, first_differing = -1;
  for (size_t k = 0; k < first.size(); ++k) {
    if (!BitwiseEqual(first[k], second[k])) {
      if (differing++ == 0) first_differing = static_cast<int>(k);
    }
  }
  EXPECT_EQ(differing, 0) << "first at frame " << first_differing;
}

TEST(ReferenceRefinerTest, WindowBeyond64KeyframesTracksAsTheSmallerOne) {
  // A keyframe every frame: 64 by frame 64, then the window of 65 eliminates the poses
  // (optim/line_pose_marginals.h) while the window of 64 keeps the lines' elimination and drops
  // its nearest keyframe. Up to the switch the two runs are the same to the bit; after it their
  // windows differ by one keyframe of 65, so their poses and reported deviations must stay close.
  const SimulatedSequence sim = RoomLoopStart(90);
  const std::vector<TrackerOutput> lines_eliminated =
      TrackWithRefinement(sim.sequence, {{"keyframe_interval", 1}, {"max_keyframes", 64}});
  const std::vector<TrackerOutput> poses_eliminated =
      TrackWithRefinement(sim.sequence, {{"keyframe_interval", 1}, {"max_keyframes", 65}});
  ASSERT_EQ(lines_eliminated.size(), poses_eliminated.size());
  const size_t switch_frame = 64;
  for (size_t k = 0; k < switch_frame; ++k) ASSERT_TRUE(BitwiseEqual(lines_eliminated[k], poses_eliminated[k])) << "frame " << k;
  double largest_difference_m = 0.0, largest_sigma_ratio = 1.0, largest_error_m = 0.0;
  for (size_t k = switch_frame; k < lines_eliminated.size(); ++k) {
    const TrackerOutput& a = lines_eliminated[k];
    const TrackerOutput& b = poses_eliminated[k];
    EXPECT_NE(b.status, TrackingStatus::kLost) << "frame " << k;
    largest_difference_m = std::max(largest_difference_m, (a.cam_from_world.Inverse().translation -
                                                           b.cam_from_world.Inverse().translation).norm());
    const double sigma_a = std::sqrt(a.covariance.bottomRightCorner<3, 3>().trace());
    const double sigma_b = std::sqrt(b.covariance.bottomRightCorner<3, 3>().trace());
    largest_sigma_ratio = std::max({largest_sigma_ratio, sigma_a / sigma_b, sigma_b / sigma_a});
    largest_error_m = std::max(largest_error_m, (b.cam_from_world.Inverse().translation -
                                                 sim.ground_truth[k].world_from_cam.translation).norm());
  }
  std::printf("poses' elimination from frame %zu: position within %.3f mm of the lines' elimination's, sigma ratio "
              "%.3f, error up to %.2f mm\n", switch_frame, 1e3 * largest_difference_m, largest_sigma_ratio, 1e3 * largest_error_m);
  EXPECT_LT(largest_difference_m, 1e-3);
  EXPECT_LT(largest_sigma_ratio, 1.1);
  EXPECT_LT(largest_error_m, 0.03);  // tracking, not diverging
}

TEST(ReferenceRefinerTest, PoseCovarianceFromTheSolve) {
  // 60 frames of the room loop, a keyframe every 5th. "report_cover" leaves every estimate as
  // the filter's own makes it and only widens the reported covariance, from the first solve on,
  // where the filter claims more than the window's data give; "solve" hands the solve's marginal
  // to the filter, which then tracks differently.
  const SimulatedSequence sim = RoomLoopStart(60);
  const nlohmann::json every5 = {{"keyframe_interval", 5}};
  const std::vector<TrackerOutput> own = TrackWithRefinement(sim.sequence, every5);
  nlohmann::json report = every5, solve = every5;
  report["pose_covariance"] = "report_cover";
  solve["pose_covariance"] = "solve";
  const std::vector<TrackerOutput> reported = TrackWithRefinement(sim.sequence, report);
  const std::vector<TrackerOutput> solved = TrackWithRefinement(sim.sequence, solve);
  ASSERT_EQ(own.size(), reported.size());
  int widened = 0, moved = 0;
  for (size_t k = 0; k < own.size(); ++k) {
    EXPECT_TRUE(own[k].cam_from_world.rotation == reported[k].cam_from_world.rotation &&
                own[k].cam_from_world.translation == reported[k].cam_from_world.translation && own[k].status == reported[k].status)
        << "frame " << k;
    const Eigen::SelfAdjointEigenSolver<Matrix6d> widening(reported[k].covariance - own[k].covariance);
    EXPECT_GE(widening.eigenvalues().minCoeff(), -1e-12 * own[k].covariance.norm()) << "frame " << k;
    widened += widening.eigenvalues().maxCoeff() > 1e-3 * own[k].covariance.norm() ? 1 : 0;
    if (k < 5) {
      EXPECT_TRUE(BitwiseEqual(own[k], solved[k])) << "frame " << k;  // before the first solve
    }
    moved += (own[k].cam_from_world.translation - solved[k].cam_from_world.translation).norm() > 1e-9 ? 1 : 0;
  }
  EXPECT_GT(widened, 20);
  EXPECT_GT(moved, 20);
}

TEST(ReferenceRefinerTest, ReferencePlacementAddedToTheReportedCovariance) {
  // "report_placement" leaves every estimate as the filter's own makes it; from the first solve
  // on the reported covariance gains the reference pair's placement moved into the current
  // camera, Ad(cam_from_ref) S Ad(cam_from_ref)^T: positive definite, and carried on through the
  // world covariance of a new reference pair. Until the first new pair cam_from_ref is
  // cam_from_world, and the term is constant in the reference frame between two solves.
  const SimulatedSequence sim = RoomLoopStart(60);
  const nlohmann::json every5 = {{"keyframe_interval", 5}};
  const std::vector<TrackerOutput> own = TrackWithRefinement(sim.sequence, every5);
  nlohmann::json placement = every5;
  placement["pose_covariance"] = "report_placement";
  const std::vector<TrackerOutput> reported = TrackWithRefinement(sim.sequence, placement);
  ASSERT_EQ(own.size(), reported.size());
  int added = 0, compared = 0;
  Matrix6d first_placement = Matrix6d::Zero();
  bool first_pair = true;
  for (size_t k = 0; k < own.size(); ++k) {
    EXPECT_TRUE(own[k].cam_from_world.rotation == reported[k].cam_from_world.rotation &&
                own[k].cam_from_world.translation == reported[k].cam_from_world.translation && own[k].status == reported[k].status)
        << "frame " << k;
    first_pair = first_pair && (k == 0 || reported[k].status != TrackingStatus::kNewReference);
    const Matrix6d extra = reported[k].covariance - own[k].covariance;
    if (k < 5) {
      EXPECT_EQ(extra.norm(), 0.0) << "frame " << k;  // before the first solve
      continue;
    }
    const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(extra);
    EXPECT_GT(eigen.eigenvalues().minCoeff(), 0.0) << "frame " << k;
    ++added;
    if (!first_pair || k >= 10) continue;  // the second solve is at frame 10
    const Matrix6d ad_inverse = Adjoint(reported[k].cam_from_world.Inverse());
    const Matrix6d in_reference = ad_inverse * extra * ad_inverse.transpose();
    if (compared++ == 0) first_placement = in_reference;
    EXPECT_LT((in_reference - first_placement).norm(), 1e-9 * first_placement.norm()) << "frame " << k;
  }
  EXPECT_EQ(added, static_cast<int>(own.size()) - 5);
  EXPECT_GE(compared, 3);
}

// Mean 6-dof NEES of the tracker with `options` on `sim` (evaluation/consistency.h).
double MeanNees(const SimulatedSequence& sim, const nlohmann::json& options) {
  std::unique_ptr<PoseTracker> tracker = TrifocalLineEkfInfo().create(options, "test");
  tracker->Reset(sim.sequence.rig);
  Trajectory estimate;
  std::vector<Matrix6d> covariances;
  for (size_t k = 0; k < sim.sequence.frames.size(); ++k) {
    const TrackerOutput out = tracker->Track(sim.sequence.frames[k]);
    estimate.push_back({sim.ground_truth[k].time, out.cam_from_world.Inverse()});
    covariances.push_back(out.covariance);
  }
  return EvaluateConsistency(sim.ground_truth, estimate, covariances).nees.mean;
}

TEST(StructureConsiderTracking, RoomLoopCovarianceIsLessOverconfidentWithTheReferenceLinesConsidered) {
  // The room loop of long_room's first trial, shortened (and so faster): the reference pairs' lines
  // measured for a hundred frames and more. Counting their error as white noise in every frame
  // makes the covariance far too small (NEES 114, 6 when consistent); with the error as consider
  // parameters the NEES must come down (35).
  const SimulatedSequence sim = RoomLoopStart(300, TrialSeed(1, 0));
  const double white = MeanNees(sim, nlohmann::json::object());
  const double considered = MeanNees(sim, {{"measurement", {{"consider_structure", true}}}});
  EXPECT_LT(considered, 0.5 * white) << "white-noise NEES " << white;
}

TEST(StructureConsiderTracking, NeedsThePoseVelocityState) {
  const nlohmann::json options = {{"filter", {{"state", "velocity"}}}, {"measurement", {{"consider_structure", true}}}};
  EXPECT_THROW(TrifocalLineEkfInfo().create(options, "test"), ConfigError);
}

}  // namespace
}  // namespace slt
