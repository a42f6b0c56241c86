#include "optim/taylor_segment_cost.h"

#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <random>

#include "geometry/numeric_jacobian.h"
#include "geometry/plucker.h"
#include "geometry/se3.h"

namespace slt {
namespace {

// A random configuration: a rig, a pose, a 3-D line in front of the cameras, and a segment
// near its image in the chosen camera (off the line by a few pixels, so h1, h2 != 0).
struct Scene {
  StereoRig rig;
  Rigid3d cam_from_world;
  double pose[kPoseAmbientSize];
  double line[kLineAmbientSize];
  Segment2d segment;
};

Scene RandomScene(std::mt19937_64& rng, bool left) {
  std::normal_distribution<double> n(0.0, 1.0);
  Scene s;
  // A rotated, shifted rig so that every block of the Jacobians is exercised.
  s.rig.right_from_left = ExpSE3((Vector6d() << -0.1, 0.01, 0.02, 0.02, -0.03, 0.01).finished());
  s.rig.right.fx = 700.0;
  s.rig.right.cx = 300.0;
  Vector6d xi;
  for (int i = 0; i < 6; ++i) xi(i) = 0.3 * n(rng);
  s.cam_from_world = ExpSE3(xi);
  PoseToParameters(s.cam_from_world, s.pose);
  // Endpoints 1-2 m in front of the left camera, mapped to the world.
  const Rigid3d world_from_cam = s.cam_from_world.Inverse();
  const Eigen::Vector3d a = world_from_cam * Eigen::Vector3d(0.2 * n(rng), 0.2 * n(rng), 1.5 + 0.2 * n(rng));
  const Eigen::Vector3d b = world_from_cam * Eigen::Vector3d(0.2 * n(rng), 0.2 * n(rng), 1.5 + 0.2 * n(rng));
  EXPECT_TRUE(LineToParameters({a.cross(b - a), b - a}, s.line));
  const Rigid3d camera_from_world = left ? s.cam_from_world : s.rig.right_from_left * s.cam_from_world;
  const PinholeCamera& camera = left ? s.rig.left : s.rig.right;
  s.segment << camera.Project(camera_from_world * a) + Eigen::Vector2d(3.0 * n(rng), 3.0 * n(rng)),
      camera.Project(camera_from_world * b) + Eigen::Vector2d(3.0 * n(rng), 3.0 * n(rng));
  return s;
}

Eigen::Vector2d Residual(const TaylorSegmentCost& cost, const double* pose, const double* line) {
  const double* parameters[] = {pose, line};
  Eigen::Vector2d r;
  EXPECT_TRUE(cost.Evaluate(parameters, r.data(), nullptr));
  return r;
}

class TaylorSegmentCostTest : public ::testing::TestWithParam<bool> {};  // left camera?

TEST_P(TaylorSegmentCostTest, SquaredNormIsTheIntegratedSquaredDistanceOverSigmaSquared) {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 5; ++trial) {
    const Scene s = RandomScene(rng, GetParam());
    const SegmentCamera camera = SegmentCamera::FromRig(s.rig, GetParam());
    const double sigma = 1.7;
    const double length = (s.segment.tail<2>() - s.segment.head<2>()).norm();
    // The projected line in pixels, straight from the geometry code.
    const Rigid3d camera_from_world = GetParam() ? s.cam_from_world : s.rig.right_from_left * s.cam_from_world;
    const Eigen::Vector3d pixel_line = PixelLineFromNormalizedLine(
        GetParam() ? s.rig.left : s.rig.right, TransformPluecker(camera_from_world, LineFromParameters(s.line)).moment);
    // Midpoint rule over 20 000 pieces of the segment.
    double integral = 0.0;
    const int pieces = 20000;
    for (int k = 0; k < pieces; ++k) {
      const double u = (k + 0.5) / pieces;
      const Eigen::Vector2d x = (1.0 - u) * s.segment.head<2>() + u * s.segment.tail<2>();
      integral += std::pow(SignedDistance(pixel_line, x), 2) * length / pieces;
    }
    TaylorSegmentCost cost;
    cost.Set(&camera, s.segment, length, sigma);
    EXPECT_NEAR(Residual(cost, s.pose, s.line).squaredNorm(), integral / (sigma * sigma), 1e-6 * integral);
    // Unweighted: the mean squared distance.
    cost.Set(&camera, s.segment, 1.0, sigma);
    EXPECT_NEAR(Residual(cost, s.pose, s.line).squaredNorm(), integral / length / (sigma * sigma), 1e-6 * integral / length);
  }
}

TEST_P(TaylorSegmentCostTest, ZeroForASegmentOnTheProjectedLine) {
  std::mt19937_64 rng(12);
  Scene s = RandomScene(rng, GetParam());
  const SegmentCamera camera = SegmentCamera::FromRig(s.rig, GetParam());
  // Move the endpoints onto the line: regenerate the segment from the line itself.
  const Rigid3d camera_from_world = GetParam() ? s.cam_from_world : s.rig.right_from_left * s.cam_from_world;
  const Eigen::Vector3d l = PixelLineFromNormalizedLine(GetParam() ? s.rig.left : s.rig.right,
                                                        TransformPluecker(camera_from_world, LineFromParameters(s.line)).moment);
  for (int e = 0; e < 2; ++e) {
    const Eigen::Vector2d x = s.segment.segment<2>(2 * e);
    s.segment.segment<2>(2 * e) = x - SignedDistance(l, x) * l.head<2>().normalized();
  }
  TaylorSegmentCost cost;
  cost.Set(&camera, s.segment, 100.0, 1.0);
  EXPECT_LT(Residual(cost, s.pose, s.line).norm(), 1e-9);
}

TEST_P(TaylorSegmentCostTest, AnalyticJacobiansMatchCeresNumericDifferentiation) {
  // Ceres's GradientChecker differentiates the residual numerically in the ambient parameters
  // and compares both the ambient Jacobians and their products with the manifolds' PlusJacobian
  // (Taylor's form in even trials, the endpoints' in odd ones).
  std::mt19937_64 rng(13);
  const PoseManifold pose_manifold;
  const LineManifold line_manifold;
  const std::vector<const ceres::Manifold*> manifolds = {&pose_manifold, &line_manifold};
  ceres::NumericDiffOptions numeric;
  numeric.ridders_relative_initial_step_size = 1e-4;  // GradientChecker uses Ridders extrapolation
  for (int trial = 0; trial < 20; ++trial) {
    const Scene s = RandomScene(rng, GetParam());
    const SegmentCamera camera = SegmentCamera::FromRig(s.rig, GetParam());
    TaylorSegmentCost cost;
    cost.Set(&camera, s.segment, 150.0, 1.3, trial % 2 == 0 ? SegmentResidual::kTaylor : SegmentResidual::kEndpoints);
    ceres::GradientChecker checker(&cost, &manifolds, numeric);
    ceres::GradientChecker::ProbeResults results;
    const double* parameters[] = {s.pose, s.line};
    EXPECT_TRUE(checker.Probe(parameters, 1e-6, &results)) << results.error_log;
    for (int block = 0; block < 2; ++block) {
      const double scale = std::max(1.0, results.numeric_jacobians[block].norm());
      EXPECT_LT((results.jacobians[block] - results.numeric_jacobians[block]).norm(), 1e-6 * scale) << "block " << block;
    }
  }
}

TEST_P(TaylorSegmentCostTest, PoseTangentJacobianAgreesWithTheGeometryCode) {
  // J_ambient * PlusJacobian = (d r / d l) * (d l / d [v; w]), the latter from
  // ImageLineInStereoPair: the residual uses the project's perturbation convention.
  std::mt19937_64 rng(14);
  const PoseManifold pose_manifold;
  for (int trial = 0; trial < 5; ++trial) {
    const Scene s = RandomScene(rng, GetParam());
    const SegmentCamera camera = SegmentCamera::FromRig(s.rig, GetParam());
    TaylorSegmentCost cost;
    cost.Set(&camera, s.segment, 80.0, 2.0);
    Eigen::Matrix<double, 2, kPoseAmbientSize, Eigen::RowMajor> ambient;
    Eigen::Vector2d r;
    const double* parameters[] = {s.pose, s.line};
    double* jacobians[] = {ambient.data(), nullptr};
    ASSERT_TRUE(cost.Evaluate(parameters, r.data(), jacobians));
    Eigen::Matrix<double, kPoseAmbientSize, 6, Eigen::RowMajor> plus;
    ASSERT_TRUE(pose_manifold.PlusJacobian(s.pose, plus.data()));

    StereoLineImages images;
    ImageLineInStereoPair(s.rig.right_from_left, s.cam_from_world, LineFromParameters(s.line), false, &images);
    const Eigen::Vector3d image = GetParam() ? images.left : images.right;
    const Matrix36d image_d_pose = GetParam() ? images.left_d_pose : images.right_d_pose;
    // d r / d l through a cost that sees the line l directly: a camera at the identity and the
    // line [l; d] with any d orthogonal to l (its moment in that camera is l).
    SegmentCamera direct = camera;
    direct.is_left = true;
    const auto residual_of_line = [&](const Eigen::Vector3d& l) {
      TaylorSegmentCost c;
      c.Set(&direct, s.segment, 80.0, 2.0);
      double identity[kPoseAmbientSize];
      PoseToParameters(Rigid3d(), identity);
      const double line[kLineAmbientSize] = {l.x(), l.y(), l.z(), 0.0, 0.0, 0.0};
      return Residual(c, identity, line);
    };
    const Eigen::Matrix<double, 2, 3> r_d_image = CentralDifferenceJacobian<2, 3>(residual_of_line, image, 1e-7);
    const Eigen::Matrix<double, 2, 6> expected = r_d_image * image_d_pose;
    const Eigen::Matrix<double, 2, 6> actual = ambient * plus;
    EXPECT_LT((actual - expected).norm(), 1e-5 * expected.norm()) << "actual\n" << actual << "\nexpected\n" << expected;
  }
}

TEST_P(TaylorSegmentCostTest, EndpointResidualIsTheEndpointsDistancesOverSigma) {
  std::mt19937_64 rng(15);
  for (int trial = 0; trial < 10; ++trial) {
    const Scene s = RandomScene(rng, GetParam());
    const SegmentCamera camera = SegmentCamera::FromRig(s.rig, GetParam());
    const Rigid3d camera_from_world = GetParam() ? s.cam_from_world : s.rig.right_from_left * s.cam_from_world;
    const Eigen::Vector3d pixel_line = PixelLineFromNormalizedLine(
        GetParam() ? s.rig.left : s.rig.right, TransformPluecker(camera_from_world, LineFromParameters(s.line)).moment);
    const double sigma = 0.7, weight = 2.0;
    TaylorSegmentCost cost;
    cost.Set(&camera, s.segment, weight, sigma, SegmentResidual::kEndpoints);
    const Eigen::Vector2d r = Residual(cost, s.pose, s.line);
    EXPECT_NEAR(r(0), std::sqrt(weight) * SignedDistance(pixel_line, s.segment.head<2>()) / sigma, 1e-9);
    EXPECT_NEAR(r(1), std::sqrt(weight) * SignedDistance(pixel_line, s.segment.tail<2>()) / sigma, 1e-9);
  }
}

INSTANTIATE_TEST_SUITE_P(Cameras, TaylorSegmentCostTest, ::testing::Values(true, false),
                         [](const ::testing::TestParamInfo<bool>& p) { return p.param ? "Left" : "Right"; });

TEST(TaylorSegmentCost, FailsForALineThroughTheCameraCentre) {
  const StereoRig rig;
  const SegmentCamera camera = SegmentCamera::FromRig(rig, true);
  TaylorSegmentCost cost;
  cost.Set(&camera, Segment2d(10, 10, 100, 100), 127.0, 1.0);
  double pose[kPoseAmbientSize];
  PoseToParameters(Rigid3d(), pose);
  const double line[kLineAmbientSize] = {0, 0, 0, 0, 0, 1};  // the optical axis
  const double* parameters[] = {pose, line};
  double r[2];
  EXPECT_FALSE(cost.Evaluate(parameters, r, nullptr));
}

TEST(WeightedSegmentLoss, IsTheRobustLossOfTheMeanSquaredDistanceTimesTheWeight) {
  const ceres::HuberLoss huber(2.0);
  WeightedSegmentLoss loss;
  const double weight = 150.0;
  loss.Set(&huber, weight);
  for (double per_length : {0.5, 3.0, 9.0}) {  // (rms / sigma)^2 below and above k^2 = 4
    const double s = weight * per_length;
    double rho[3], expected[3];
    loss.Evaluate(s, rho);
    huber.Evaluate(per_length, expected);
    EXPECT_DOUBLE_EQ(rho[0], weight * expected[0]);
    // Derivatives against central differences of rho itself.
    const double h = 1e-4 * s;
    double plus[3], minus[3];
    loss.Evaluate(s + h, plus);
    loss.Evaluate(s - h, minus);
    EXPECT_NEAR(rho[1], (plus[0] - minus[0]) / (2 * h), 1e-6);
    EXPECT_NEAR(rho[2], (plus[1] - minus[1]) / (2 * h), 1e-6);
  }
  // Inliers keep Taylor's weighting: rho(s) = s.
  double rho[3];
  loss.Evaluate(weight * 1.0, rho);
  EXPECT_DOUBLE_EQ(rho[0], weight * 1.0);
  loss.Set(nullptr, weight);
  loss.Evaluate(1234.0, rho);
  EXPECT_EQ(rho[0], 1234.0);
  EXPECT_EQ(rho[1], 1.0);
  EXPECT_EQ(rho[2], 0.0);
}

}  // namespace
}  // namespace slt
