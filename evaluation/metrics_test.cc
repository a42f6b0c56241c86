#include "evaluation/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/json_reader.h"
#include "geometry/se3.h"

namespace slt {
namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Matrix3d RotationAbout(const Eigen::Vector3d& axis, double degrees) {
  return Eigen::AngleAxisd(degrees * kPi / 180.0, axis.normalized()).toRotationMatrix();
}

// A camera wandering and turning: every pose differs, positions span 3-D.
Trajectory WanderingTrajectory(int n, double period = 0.1) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> step(-1.0, 1.0);
  Trajectory trajectory;
  Rigid3d world_from_cam;
  for (int k = 0; k < n; ++k) {
    trajectory.push_back({k * period, world_from_cam});
    Vector6d xi;
    xi << 0.02 * step(rng), 0.02 * step(rng), 0.02 * step(rng), 0.02 * step(rng), 0.02 * step(rng),
        0.02 * step(rng);
    world_from_cam = world_from_cam * ExpSE3(xi);
  }
  return trajectory;
}

TEST(Metrics, IdenticalTrajectoriesHaveZeroError) {
  const Trajectory gt = WanderingTrajectory(50);
  const TrajectoryErrors e = EvaluateTrajectory(gt, gt, EvaluationOptions{});
  EXPECT_EQ(e.associated_poses, 50u);
  EXPECT_EQ(e.ate_trans_m.count, 50u);
  EXPECT_EQ(e.ate_trans_m.max, 0.0);
  EXPECT_EQ(e.ate_rot_deg.max, 0.0);
  EXPECT_EQ(e.rpe_trans_m.count, 49u);
  EXPECT_LT(e.rpe_trans_m.max, 1e-15);
  EXPECT_LT(e.rpe_rot_deg.max, 1e-12);
  EXPECT_EQ(e.Final().frame, 49);
  EXPECT_EQ(e.Final().trans_err_m, 0.0);
}

TEST(Metrics, ConstantOffsetGivesThatAte) {
  const Trajectory gt = WanderingTrajectory(30);
  Trajectory est = gt;
  for (TimedPose& pose : est) pose.world_from_cam.translation += Eigen::Vector3d(0.03, -0.04, 0.0);
  const TrajectoryErrors e = EvaluateTrajectory(gt, est, EvaluationOptions{});
  EXPECT_NEAR(e.ate_trans_m.rmse, 0.05, 1e-15);
  EXPECT_NEAR(e.ate_trans_m.mean, 0.05, 1e-15);
  EXPECT_NEAR(e.ate_trans_m.median, 0.05, 1e-15);
  EXPECT_NEAR(e.ate_trans_m.min, 0.05, 1e-15);
  EXPECT_NEAR(e.ate_trans_m.max, 0.05, 1e-15);
  EXPECT_LT(e.ate_trans_m.std, 1e-15);
  EXPECT_NEAR(e.Final().trans_err_m, 0.05, 1e-15);
  EXPECT_EQ(e.ate_rot_deg.max, 0.0);
  // A world shift does not change any relative motion.
  EXPECT_LT(e.rpe_trans_m.max, 1e-14);

  // An SE(3) alignment removes the offset.
  EvaluationOptions aligned;
  aligned.alignment = Alignment::kSE3;
  const TrajectoryErrors a = EvaluateTrajectory(gt, est, aligned);
  EXPECT_LT(a.ate_trans_m.max, 1e-12);
  EXPECT_TRUE(a.alignment.translation.isApprox(Eigen::Vector3d(-0.03, 0.04, 0.0), 1e-10));
}

TEST(Metrics, RotationErrorOfKnownAngle) {
  const Trajectory gt = WanderingTrajectory(30);
  Trajectory est = gt;
  // The camera turned 2 degrees more than it should, about its own axis (any axis: the angle
  // of R_gt^T R_est is what counts), with its centre in the right place.
  for (TimedPose& pose : est) pose.world_from_cam.rotation *= RotationAbout({0.3, -1.0, 0.2}, 2.0);
  const TrajectoryErrors e = EvaluateTrajectory(gt, est, EvaluationOptions{});
  EXPECT_NEAR(e.ate_rot_deg.rmse, 2.0, 1e-9);
  EXPECT_NEAR(e.ate_rot_deg.min, 2.0, 1e-9);
  EXPECT_NEAR(e.ate_rot_deg.max, 2.0, 1e-9);
  EXPECT_NEAR(e.Final().rot_err_deg, 2.0, 1e-9);
  EXPECT_EQ(e.ate_trans_m.max, 0.0);
}

TEST(Metrics, UmeyamaRecoversSimilarity) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  SimilarityTransform truth;
  truth.rotation = RotationAbout({1.0, 2.0, -0.5}, 70.0);
  truth.translation = Eigen::Vector3d(0.5, -2.0, 3.0);
  truth.scale = 2.5;
  std::vector<Eigen::Vector3d> source, target;
  for (int i = 0; i < 10; ++i) {
    source.emplace_back(normal(rng), normal(rng), normal(rng));
    target.push_back(truth * source.back());
  }
  const SimilarityTransform sim3 = UmeyamaAlignment(source, target, true);
  EXPECT_TRUE(sim3.rotation.isApprox(truth.rotation, 1e-12));
  EXPECT_TRUE(sim3.translation.isApprox(truth.translation, 1e-12));
  EXPECT_NEAR(sim3.scale, truth.scale, 1e-12);

  // Without scale, on a rigid motion of the points.
  truth.scale = 1.0;
  for (size_t i = 0; i < source.size(); ++i) target[i] = truth * source[i];
  const SimilarityTransform se3 = UmeyamaAlignment(source, target, false);
  EXPECT_TRUE(se3.rotation.isApprox(truth.rotation, 1e-12));
  EXPECT_TRUE(se3.translation.isApprox(truth.translation, 1e-12));
  EXPECT_EQ(se3.scale, 1.0);
}

TEST(Metrics, UmeyamaRejectsDegeneratePoints) {
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {1, 1, 0}, {2, 2, 0}, {3, 3, 0}};
  EXPECT_THROW(UmeyamaAlignment(line, line, false), std::invalid_argument);
  const std::vector<Eigen::Vector3d> two = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_THROW(UmeyamaAlignment(two, two, false), std::invalid_argument);
  EXPECT_THROW(UmeyamaAlignment(line, two, false), std::invalid_argument);
}

// The estimate lives in another world: est = S * gt for a similarity S. Alignment must find
// S^-1 and leave no error; without alignment the error is large.
TEST(Metrics, AlignmentRecoversKnownTransform) {
  const Trajectory gt = WanderingTrajectory(40);
  SimilarityTransform est_world_from_gt_world;
  est_world_from_gt_world.rotation = RotationAbout({0.2, 1.0, 0.4}, 35.0);
  est_world_from_gt_world.translation = Eigen::Vector3d(1.0, -0.5, 0.25);

  Trajectory est = gt;
  for (TimedPose& pose : est) pose.world_from_cam = est_world_from_gt_world.Apply(pose.world_from_cam);
  EvaluationOptions options;
  EXPECT_GT(EvaluateTrajectory(gt, est, options).ate_trans_m.rmse, 0.1);
  options.alignment = Alignment::kSE3;
  TrajectoryErrors e = EvaluateTrajectory(gt, est, options);
  EXPECT_LT(e.ate_trans_m.max, 1e-12);
  EXPECT_LT(e.ate_rot_deg.max, 1e-10);
  EXPECT_TRUE(e.alignment.rotation.isApprox(est_world_from_gt_world.rotation.transpose(), 1e-12));

  est_world_from_gt_world.scale = 0.4;  // a monocular-like scale error
  est = gt;
  for (TimedPose& pose : est) pose.world_from_cam = est_world_from_gt_world.Apply(pose.world_from_cam);
  options.alignment = Alignment::kSE3;
  EXPECT_GT(EvaluateTrajectory(gt, est, options).ate_trans_m.rmse, 0.01);
  options.alignment = Alignment::kSim3;
  e = EvaluateTrajectory(gt, est, options);
  EXPECT_NEAR(e.alignment.scale, 1.0 / 0.4, 1e-10);
  EXPECT_LT(e.ate_trans_m.max, 1e-12);
  // Scale-corrected relative motions match again.
  EXPECT_LT(e.rpe_trans_m.max, 1e-12);
}

// est follows gt's relative motions except between frames 4 and 5, where it makes an extra
// motion `bad` (expressed in camera 4). Only that RPE pair sees it, with the size of `bad`.
Trajectory WithBadStep(const Trajectory& gt, const Rigid3d& bad) {
  Trajectory est = gt;
  const Rigid3d drift = gt[4].world_from_cam * bad * gt[4].world_from_cam.Inverse();
  for (size_t k = 5; k < est.size(); ++k) est[k].world_from_cam = drift * gt[k].world_from_cam;
  return est;
}

TEST(Metrics, RpeSeesASingleBadStep) {
  const Trajectory gt = WanderingTrajectory(21);
  const Trajectory est_t = WithBadStep(gt, Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.0, 0.06, 0.08)));
  TrajectoryErrors e = EvaluateTrajectory(gt, est_t, EvaluationOptions{});
  ASSERT_EQ(e.rpe_trans_m.count, 20u);
  EXPECT_NEAR(e.rpe_trans_m.max, 0.1, 1e-12);
  EXPECT_NEAR(e.rpe_trans_m.rmse, 0.1 / std::sqrt(20.0), 1e-12);
  EXPECT_NEAR(e.rpe_trans_m.mean, 0.1 / 20.0, 1e-12);
  EXPECT_LT(e.rpe_trans_m.median, 1e-12);
  EXPECT_LT(e.rpe_rot_deg.max, 1e-10);
  // The absolute error, by contrast, persists after the bad step.
  EXPECT_LT(e.per_frame[4].trans_err_m, 1e-15);
  EXPECT_GT(e.Final().trans_err_m, 0.05);

  const Trajectory est_r = WithBadStep(gt, Rigid3d(RotationAbout({1.0, 0.0, 1.0}, 3.0), Eigen::Vector3d::Zero()));
  e = EvaluateTrajectory(gt, est_r, EvaluationOptions{});
  EXPECT_NEAR(e.rpe_rot_deg.max, 3.0, 1e-9);
  EXPECT_NEAR(e.rpe_rot_deg.mean, 3.0 / 20.0, 1e-9);
  EXPECT_LT(e.rpe_rot_deg.median, 1e-10);
}

TEST(Metrics, RpeDeltaPairsFollowEvo) {
  const Trajectory gt = WanderingTrajectory(10);
  const Trajectory est = WithBadStep(gt, Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.1, 0.0, 0.0)));
  EvaluationOptions options;
  options.rpe_delta_frames = 2;
  // Pairs (0,2) (2,4) (4,6) (6,8): the bad step 4 -> 5 lies in (4,6).
  TrajectoryErrors e = EvaluateTrajectory(gt, est, options);
  EXPECT_EQ(e.rpe_trans_m.count, 4u);
  EXPECT_NEAR(e.rpe_trans_m.max, 0.1, 1e-12);
  EXPECT_NEAR(e.rpe_trans_m.mean, 0.1 / 4.0, 1e-12);
  // All pairs (i, i+2), i = 0..7: (3,5) and (4,6) contain it.
  options.rpe_all_pairs = true;
  e = EvaluateTrajectory(gt, est, options);
  EXPECT_EQ(e.rpe_trans_m.count, 8u);
  EXPECT_NEAR(e.rpe_trans_m.mean, 2 * 0.1 / 8.0, 1e-12);
}

TEST(Metrics, AssociationToleratesJitterAndUsesEachGroundTruthPoseOnce) {
  const Trajectory gt = WanderingTrajectory(10);  // times 0, 0.1, ..., 0.9
  Trajectory est;
  const double jitter[] = {0.004, -0.003, 0.0, 0.009, -0.008};
  for (int k = 0; k < 5; ++k) est.push_back({gt[2 * k].time + jitter[k], gt[2 * k].world_from_cam});
  std::vector<PosePair> pairs = AssociateByTime(gt, est, 0.01);
  ASSERT_EQ(pairs.size(), 5u);
  for (size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(pairs[k].est_index, k);
    EXPECT_EQ(pairs[k].gt_index, 2 * k);
  }
  const TrajectoryErrors e = EvaluateTrajectory(gt, est, EvaluationOptions{});
  EXPECT_EQ(e.associated_poses, 5u);
  EXPECT_EQ(e.ate_trans_m.max, 0.0);
  EXPECT_EQ(e.Final().frame, 8);
  EXPECT_EQ(e.Final().time_s, gt[8].time);

  // A tighter window drops the poses jittered beyond it.
  EXPECT_EQ(AssociateByTime(gt, est, 0.005).size(), 3u);

  // Two estimate poses nearest to ground-truth pose 3: the nearer keeps it, the other stays
  // out even though pose 2 is free (evo's nearest-neighbour rule, made one-to-one).
  est = {{0.2, gt[2].world_from_cam}, {0.297, gt[3].world_from_cam}, {0.3015, gt[3].world_from_cam}};
  pairs = AssociateByTime(gt, est, 0.01);
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0].est_index, 0u);
  EXPECT_EQ(pairs[0].gt_index, 2u);
  EXPECT_EQ(pairs[1].est_index, 2u);
  EXPECT_EQ(pairs[1].gt_index, 3u);
}

TEST(Metrics, ErrorsWhenNothingAssociatesOrOptionsAreInvalid) {
  const Trajectory gt = WanderingTrajectory(5);
  Trajectory est = gt;
  for (TimedPose& pose : est) pose.time += 100.0;
  EXPECT_THROW(EvaluateTrajectory(gt, est, EvaluationOptions{}), std::invalid_argument);
  EXPECT_THROW(EvaluateTrajectory(gt, Trajectory{}, EvaluationOptions{}), std::invalid_argument);
  EXPECT_THROW(EvaluateTrajectory(gt, Trajectory(gt.begin(), gt.begin() + 1), EvaluationOptions{}),
               std::invalid_argument);

  EvaluationOptions options;
  options.rpe_delta_frames = 0;
  try {
    options.Check("--rpe-delta");
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "--rpe-delta: key 'rpe_delta_frames': must be >= 1");
  }
  options.rpe_delta_frames = 1;
  options.max_time_diff_s = -1.0;
  EXPECT_THROW(options.Check(), ConfigError);
  EXPECT_THROW(AlignmentFromName("sim2"), std::invalid_argument);
  EXPECT_EQ(AlignmentFromName("sim3"), Alignment::kSim3);
}

TEST(Metrics, StatisticsMatchEvoDefinitions) {
  const ErrorStatistics s = ComputeStatistics({3.0, 1.0, 4.0, 2.0});
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(30.0 / 4.0));
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));  // population std, as numpy's default
  EXPECT_EQ(s.min, 1.0);
  EXPECT_EQ(s.max, 4.0);
  EXPECT_EQ(ComputeStatistics({5.0, 1.0, 2.0}).median, 2.0);
}

TEST(Metrics, MeanErrorCurveAveragesTrialsFrameByFrame) {
  const ErrorCurve a = {{0, 0.0, 0.0, 0.0}, {1, 0.1, 0.002, 0.1}, {2, 0.2, 0.004, 0.3}};
  const ErrorCurve b = {{0, 0.0, 0.0, 0.0}, {1, 0.1, 0.004, 0.2}, {2, 0.2, 0.010, 0.6}};
  const ErrorCurve mean = MeanErrorCurve({a, b});
  ASSERT_EQ(mean.size(), 3u);
  EXPECT_EQ(mean[2].frame, 2);
  EXPECT_DOUBLE_EQ(mean[2].time_s, 0.2);
  EXPECT_DOUBLE_EQ(mean[1].trans_err_m, 0.003);
  EXPECT_DOUBLE_EQ(mean[2].trans_err_m, 0.007);
  EXPECT_DOUBLE_EQ(mean[2].rot_err_deg, 0.45);
  EXPECT_DOUBLE_EQ(ErrorAtFrame(mean, 1).rot_err_deg, 0.15);
  EXPECT_THROW(ErrorAtFrame(mean, 3), std::out_of_range);

  EXPECT_THROW(MeanErrorCurve({}), std::invalid_argument);
  EXPECT_THROW(MeanErrorCurve({a, ErrorCurve(a.begin(), a.begin() + 2)}), std::invalid_argument);
  ErrorCurve shifted = b;
  shifted[1].frame = 5;
  EXPECT_THROW(MeanErrorCurve({a, shifted}), std::invalid_argument);
}

// The curve of an unaligned evaluation is the paper's accumulated error: at frame k, the
// error of pose k against the truth in the shared world.
TEST(Metrics, PerFrameCurveIsTheAccumulatedError) {
  const Trajectory gt = WanderingTrajectory(12);
  const Trajectory est = WithBadStep(gt, Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.0, 0.0, 0.02)));
  const TrajectoryErrors e = EvaluateTrajectory(gt, est, EvaluationOptions{});
  ASSERT_EQ(e.per_frame.size(), 12u);
  for (int k = 0; k < 12; ++k) {
    EXPECT_EQ(e.per_frame[k].frame, k);
    EXPECT_NEAR(e.per_frame[k].trans_err_m,
                (est[k].world_from_cam.translation - gt[k].world_from_cam.translation).norm(), 1e-15);
  }
  const nlohmann::json j = ToJson(e, true);
  EXPECT_EQ(j["alignment"], "none");
  EXPECT_EQ(j["associated_poses"], 12);
  EXPECT_EQ(j["final_frame"], 11);
  EXPECT_EQ(j["final_trans_err_m"], e.per_frame.back().trans_err_m);
  EXPECT_EQ(j["ate_trans_m"]["rmse"], e.ate_trans_m.rmse);
  EXPECT_EQ(j["rpe_rot_deg"]["count"], 11);
  EXPECT_EQ(j["per_frame"]["trans_err_m"].size(), 12u);
  EXPECT_FALSE(ToJson(e, false).contains("per_frame"));
}

// A straight drive along z, 1 m per frame, 10 Hz, and an estimate that overestimates each
// step by 1 % and turns by 0.01 deg per frame about its y axis.
TEST(KittiOdometry, KnownScaleAndRotationDrift) {
  Trajectory gt, est;
  for (int k = 0; k <= 200; ++k) {
    gt.push_back({0.1 * k, Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, k))});
    est.push_back({0.1 * k, Rigid3d(RotationAbout(Eigen::Vector3d::UnitY(), 0.01 * k), Eigen::Vector3d(0, 0, 1.01 * k))});
  }
  const KittiOdometryErrors errors = EvaluateKittiOdometry(gt, est, KittiOdometryOptions());
  EXPECT_DOUBLE_EQ(errors.path_length_m, 200.0);
  // 100 m: the first pose beyond d(i) + 100 is i + 101, for i = 0, 10, ..., 90; 200 m and more
  // need 201 steps: none.
  EXPECT_EQ(errors.segments, 10);
  ASSERT_EQ(errors.per_length.size(), 8u);
  EXPECT_EQ(errors.per_length[0].segments, 10);
  EXPECT_EQ(errors.per_length[1].segments, 0);
  EXPECT_TRUE(std::isnan(errors.per_length[1].trans_err_pct));
  // Rotation: 101 frames of 0.01 deg over 100 m.
  EXPECT_NEAR(errors.rot_err_deg_per_m, 1.01 / 100.0, 1e-9);
  // Translation: ||t(E)|| = ||t_gt - t_est|| of the two motions from pose i: 101 m along z
  // against 1.01 * 101 m along z turned by the estimate's heading at i, 0.01 i deg.
  double expected_pct = 0.0;
  for (int i = 0; i <= 90; i += 10) {
    const double a = 101.0, b = 1.01 * 101.0, heading = 0.01 * i * M_PI / 180.0;
    expected_pct += 100.0 * std::sqrt(a * a + b * b - 2.0 * a * b * std::cos(heading)) / 100.0 / 10.0;
  }
  EXPECT_NEAR(errors.trans_err_pct, expected_pct, 1e-9);
  EXPECT_GT(errors.trans_err_pct, 1.01);
  EXPECT_EQ(ToJson(errors)["segments"], 10);

  // Without scale error and rotation: zero.
  const KittiOdometryErrors exact = EvaluateKittiOdometry(gt, gt, KittiOdometryOptions());
  EXPECT_DOUBLE_EQ(exact.trans_err_pct, 0.0);
  EXPECT_DOUBLE_EQ(exact.rot_err_deg_per_m, 0.0);
}

TEST(KittiOdometry, ShortSequencesHaveNoSegmentsAndOptionsAreChecked) {
  Trajectory gt;
  for (int k = 0; k < 51; ++k) gt.push_back({0.1 * k, Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(k, 0, 0))});
  const KittiOdometryErrors errors = EvaluateKittiOdometry(gt, gt, KittiOdometryOptions());
  EXPECT_EQ(errors.segments, 0);
  EXPECT_TRUE(std::isnan(errors.trans_err_pct));
  EXPECT_TRUE(ToJson(errors)["trans_err_pct"].is_null());
  KittiOdometryOptions shorter;
  shorter.segment_lengths_m = {10, 20};
  // i + 11 <= 50: i = 0, 10, 20, 30; i + 21 <= 50: i = 0, 10, 20.
  EXPECT_EQ(EvaluateKittiOdometry(gt, gt, shorter).segments, 4 + 3);
  shorter.segment_lengths_m = {};
  EXPECT_THROW(EvaluateKittiOdometry(gt, gt, shorter), ConfigError);
  shorter.segment_lengths_m = {-1};
  EXPECT_THROW(EvaluateKittiOdometry(gt, gt, shorter), ConfigError);
}

}  // namespace
}  // namespace slt
