#include "simulator/motion.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "geometry/se3.h"

namespace slt {
namespace {

constexpr double kDeg = M_PI / 180.0;

// cam_k_from_cam_{k-1}: the body-frame increment between two consecutive poses.
Rigid3d Increment(const Trajectory& t, std::size_t k) {
  return t[k].world_from_cam.Inverse() * t[k - 1].world_from_cam;
}

double PoseError(const Rigid3d& a, const Rigid3d& b) {
  return (a.ToMatrix4() - b.ToMatrix4()).cwiseAbs().maxCoeff();
}

MotionConfig Motion(MotionType type) {
  MotionConfig c;
  c.type = type;
  return c;
}

TEST(Motion, FirstPoseIsIdentityAndTimesFollowTheFrameRate) {
  for (MotionType type : {MotionType::kPaper, MotionType::kLoop, MotionType::kForward, MotionType::kStatic,
                          MotionType::kPureRotation}) {
    const Trajectory t = MakeTrajectory(Motion(type), 100, 30.0, 3);
    ASSERT_EQ(t.size(), 100u) << MotionTypeName(type);
    EXPECT_TRUE(t[0].world_from_cam.rotation.isIdentity(0.0)) << MotionTypeName(type);
    EXPECT_TRUE(t[0].world_from_cam.translation.isZero(0.0)) << MotionTypeName(type);
    EXPECT_EQ(t[0].time, 0.0);
    EXPECT_DOUBLE_EQ(t[99].time, 99.0 / 30.0);
  }
}

TEST(Motion, PaperIncrementsRespectTheBoundsAndComeClose) {
  for (const auto& [max_deg, max_m] : {std::pair{1.2, 0.010}, std::pair{0.3, 0.002}}) {
    MotionConfig c = Motion(MotionType::kPaper);
    c.sinusoid.max_rotation_deg = max_deg;
    c.sinusoid.max_translation_m = max_m;
    double largest_angle = 0.0, largest_step = 0.0;
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
      const Trajectory t = MakeTrajectory(c, 100, 30.0, seed);
      for (std::size_t k = 1; k < t.size(); ++k) {
        const Rigid3d step = Increment(t, k);
        const double angle = RotationAngle(step.rotation), distance = step.translation.norm();
        EXPECT_LE(angle, max_deg * kDeg * (1.0 + 1e-9));
        EXPECT_LE(distance, max_m * (1.0 + 1e-9));
        largest_angle = std::max(largest_angle, angle);
        largest_step = std::max(largest_step, distance);
      }
    }
    // Not a motion that trivially meets the bounds by barely moving.
    EXPECT_GT(largest_angle, 0.8 * max_deg * kDeg);
    EXPECT_GT(largest_step, 0.8 * max_m);
  }
}

TEST(Motion, PaperIsSmooth) {
  // Each twist component is A sin(2 pi k / P + phi) with P >= period_min_frames, so from one
  // frame to the next the twist changes by at most bound * 2 pi / period_min_frames per triple.
  const MotionConfig c = Motion(MotionType::kPaper);
  const double rotation_jump = c.sinusoid.max_rotation_deg * kDeg * 2.0 * M_PI / c.sinusoid.period_min_frames;
  const double translation_jump = c.sinusoid.max_translation_m * 2.0 * M_PI / c.sinusoid.period_min_frames;
  const Trajectory t = MakeTrajectory(c, 100, 30.0, 11);
  for (std::size_t k = 2; k < t.size(); ++k) {
    const Vector6d change = LogSE3(Increment(t, k)) - LogSE3(Increment(t, k - 1));
    EXPECT_LE(change.tail<3>().norm(), rotation_jump * (1.0 + 1e-6));
    EXPECT_LE(change.head<3>().norm(), translation_jump * (1.0 + 1e-6));
  }
}

TEST(Motion, PureRotationTurnsAboutTheCentreLikeThePaperMotion) {
  const Trajectory paper = MakeTrajectory(Motion(MotionType::kPaper), 100, 30.0, 8);
  const Trajectory rotation = MakeTrajectory(Motion(MotionType::kPureRotation), 100, 30.0, 8);
  double largest_angle = 0.0;
  for (std::size_t k = 0; k < rotation.size(); ++k) {
    EXPECT_EQ(rotation[k].world_from_cam.translation.norm(), 0.0);
    EXPECT_LT((rotation[k].world_from_cam.rotation - paper[k].world_from_cam.rotation).norm(), 1e-15);
    largest_angle = std::max(largest_angle, RotationAngle(rotation[k].world_from_cam.rotation));
  }
  EXPECT_GT(largest_angle, 2.0 * kDeg);
}

TEST(Motion, StaticNeverMoves) {
  for (const TimedPose& pose : MakeTrajectory(Motion(MotionType::kStatic), 50, 30.0, 1)) {
    EXPECT_TRUE(pose.world_from_cam.rotation.isIdentity(0.0));
    EXPECT_TRUE(pose.world_from_cam.translation.isZero(0.0));
  }
}

TEST(Motion, LoopReturnsToItsStart) {
  const MotionConfig c = Motion(MotionType::kLoop);
  for (int frames : {2, 3, 100, 517}) {
    const Trajectory t = MakeTrajectory(c, frames, 30.0, 4);
    EXPECT_LT(PoseError(t.back().world_from_cam, Rigid3d::Identity()), 1e-9) << frames;
  }
  const Trajectory t = MakeTrajectory(c, 100, 30.0, 4);
  double farthest = 0.0, largest_yaw = 0.0;
  for (const TimedPose& pose : t) {
    farthest = std::max(farthest, pose.world_from_cam.translation.norm());
    largest_yaw = std::max(largest_yaw, RotationAngle(pose.world_from_cam.rotation));
  }
  EXPECT_GT(farthest, 2.0 * c.loop.radius_x_m * 0.99);  // it does go round
  EXPECT_GT(largest_yaw, c.loop.yaw_amplitude_deg * kDeg * 0.95);
  // Smooth: no frame-to-frame step larger than the ellipse's perimeter share allows.
  for (std::size_t k = 1; k < t.size(); ++k) {
    EXPECT_LT(Increment(t, k).translation.norm(), 0.05);
    EXPECT_LT(RotationAngle(Increment(t, k).rotation), 1.5 * kDeg);
  }
}

TEST(Motion, ForwardAdvancesAlongZ) {
  const MotionConfig c = Motion(MotionType::kForward);
  const Trajectory t = MakeTrajectory(c, 100, 30.0, 6);
  for (std::size_t k = 0; k < t.size(); ++k) {
    EXPECT_DOUBLE_EQ(t[k].world_from_cam.translation.z(), c.forward.step_m * k);
    EXPECT_LE(t[k].world_from_cam.translation.head<2>().norm(), 2.0 * std::sqrt(2.0) * c.forward.wobble_m + 1e-12);
  }
}

TEST(Motion, SeedSelectsTheMotion) {
  const MotionConfig c = Motion(MotionType::kPaper);
  const Trajectory a = MakeTrajectory(c, 30, 30.0, 1), b = MakeTrajectory(c, 30, 30.0, 1);
  const Trajectory other = MakeTrajectory(c, 30, 30.0, 2);
  EXPECT_EQ(PoseError(a.back().world_from_cam, b.back().world_from_cam), 0.0);
  EXPECT_GT(PoseError(a.back().world_from_cam, other.back().world_from_cam), 1e-3);
}

}  // namespace
}  // namespace slt

namespace slt {
namespace {

MotionConfig Profile(MotionProfile profile) {
  MotionConfig c;
  c.profile = profile;
  return c;
}

// Per-frame speed (m/s) and angular rate (deg/s) of the increments.
struct Rates {
  std::vector<double> speed, rate;
};
Rates RatesOf(const Trajectory& t, double frame_rate) {
  Rates r;
  for (std::size_t k = 1; k < t.size(); ++k) {
    const Rigid3d step = t[k - 1].world_from_cam.Inverse() * t[k].world_from_cam;
    r.speed.push_back(step.translation.norm() * frame_rate);
    r.rate.push_back(LogSO3(step.rotation).norm() / kDeg * frame_rate);
  }
  return r;
}
double Mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (const double x : v) sum += x;
  return sum / static_cast<double>(v.size());
}
double Max(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

TEST(MotionProfile, EveryProfileStartsAtTheIdentityAndFollowsItsSeed) {
  for (const MotionProfile p : {MotionProfile::kHandheld, MotionProfile::kMav, MotionProfile::kCar}) {
    const Trajectory a = MakeTrajectory(Profile(p), 200, 20.0, 5), b = MakeTrajectory(Profile(p), 200, 20.0, 5);
    const Trajectory c = MakeTrajectory(Profile(p), 200, 20.0, 6);
    EXPECT_TRUE(a[0].world_from_cam.rotation.isIdentity(0.0)) << MotionProfileName(p);
    EXPECT_TRUE(a[0].world_from_cam.translation.isZero(0.0)) << MotionProfileName(p);
    EXPECT_EQ(PoseError(a[150].world_from_cam, b[150].world_from_cam), 0.0) << MotionProfileName(p);
    EXPECT_GT(PoseError(a[150].world_from_cam, c[150].world_from_cam), 1e-4) << MotionProfileName(p);
    // Overrides motion.type.
    MotionConfig loop = Profile(p);
    loop.type = MotionType::kLoop;
    EXPECT_EQ(PoseError(MakeTrajectory(loop, 200, 20.0, 5)[150].world_from_cam, a[150].world_from_cam), 0.0);
  }
}

TEST(MotionProfile, HandheldMovesAboutAMillimetreAndATenthOfADegreePerFrame) {
  const Rates r = RatesOf(MakeTrajectory(Profile(MotionProfile::kHandheld), 1428, 30.0, 1), 30.0);
  EXPECT_NEAR(Mean(r.speed) / 30.0, 0.001, 0.0005);
  EXPECT_NEAR(Mean(r.rate) / 30.0, 0.1, 0.05);
  EXPECT_LT(Max(r.speed) / 30.0, 0.003);
  EXPECT_LT(Max(r.rate) / 30.0, 0.3);
}

TEST(MotionProfile, MavReachesButKeepsItsPeakSpeedAndYawRateAndStaysInItsBox) {
  const MavMotionConfig c;
  for (const std::uint64_t seed : {1, 2, 3}) {
    const Trajectory t = MakeTrajectory(Profile(MotionProfile::kMav), 400, 20.0, seed);
    const Rates r = RatesOf(t, 20.0);
    // The jitter and the tilt add a little to the planned peaks.
    EXPECT_LT(Max(r.speed), 1.1 * c.max_speed_mps) << seed;
    EXPECT_GT(Max(r.speed), 0.6 * c.max_speed_mps) << seed;
    EXPECT_LT(Max(r.rate), 1.15 * c.max_yaw_rate_dps) << seed;
    EXPECT_GT(Max(r.rate), 0.5 * c.max_yaw_rate_dps) << seed;
    for (const TimedPose& pose : t) {
      const Eigen::Vector3d slack = c.extent_m + Eigen::Vector3d::Constant(2.0 * c.hover_jitter_m);
      EXPECT_TRUE((pose.world_from_cam.translation.cwiseAbs().array() <= slack.array()).all()) << seed;
      // Upright: the camera's y axis within 15 deg of the world's down.
      EXPECT_GT(pose.world_from_cam.rotation.col(1).y(), std::cos(15.0 * kDeg)) << seed;
    }
  }
}

TEST(MotionProfile, CarIsAtSpeedOnTheFirstFrameAndTurnsAsConfigured) {
  const CarMotionConfig c;
  const Trajectory t = MakeTrajectory(Profile(MotionProfile::kCar), 200, 10.0, 1);
  const Rates r = RatesOf(t, 10.0);
  EXPECT_NEAR(r.speed.front(), c.cruise_speed_mps, 0.05);
  for (const double v : r.speed) {
    EXPECT_GE(v, 5.0);
    EXPECT_LE(v, 15.0);
  }
  // Up to 30 deg/s in the turn (the yaw rate of the arc, v / R, plus the body's motion).
  EXPECT_GT(Max(r.rate), 25.0);
  EXPECT_LT(Max(r.rate), 31.0);
  // The heading at the end: turned right by turn_deg, level within the suspension's tilt.
  const Eigen::Vector3d forward = t.back().world_from_cam.rotation.col(2);
  EXPECT_NEAR(std::atan2(forward.x(), forward.z()) / kDeg, c.turn_deg, 1.0);
  EXPECT_LT(std::abs(forward.y()), std::sin(1.0 * kDeg));
  // On the route: the camera's centre within the suspension's travel of CarRoute's.
  const CarRoute route(c);
  std::vector<double> times;
  for (const TimedPose& pose : t) times.push_back(pose.time);
  const std::vector<double> s = route.Distances(times);
  for (std::size_t k = 0; k < t.size(); ++k) {
    EXPECT_LT((t[k].world_from_cam.translation - route.Position(s[k])).norm(), 2.0 * c.suspension_m) << k;
  }
}

TEST(MotionProfile, CarRouteIsContinuousAndMeetsItsSpeeds) {
  const CarMotionConfig c;
  const CarRoute route(c);
  EXPECT_EQ(route.Speed(0.0), c.cruise_speed_mps);
  EXPECT_EQ(route.Speed(c.straight_m + 1.0), c.turn_speed_mps);
  const double arc_end = c.straight_m + c.turn_radius_m * c.turn_deg * kDeg;
  EXPECT_NEAR(route.Position(arc_end).x(), c.turn_radius_m, 1e-9);
  EXPECT_NEAR(route.Position(arc_end).z(), c.straight_m + c.turn_radius_m, 1e-9);
  for (double s = 0.0; s < arc_end + 50.0; s += 0.25) {
    EXPECT_NEAR((route.Position(s + 0.25) - route.Position(s)).norm(), 0.25, 1e-3) << s;
    EXPECT_LE(std::abs(route.LongitudinalAcceleration(s)), std::max(c.brake_mps2, c.accelerate_mps2) + 1e-6) << s;
  }
  // A left turn mirrors it.
  CarMotionConfig left = c;
  left.turn_deg = -c.turn_deg;
  EXPECT_NEAR(CarRoute(left).Position(arc_end).x(), -c.turn_radius_m, 1e-9);
}

}  // namespace
}  // namespace slt
