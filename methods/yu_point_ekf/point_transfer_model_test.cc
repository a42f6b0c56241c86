#include "methods/yu_point_ekf/point_transfer_model.h"

#include <gtest/gtest.h>

#include "geometry/numeric_jacobian.h"
#include "geometry/se3.h"
#include "geometry/trifocal.h"
#include "methods/stereo_ekf/tiny_scene.h"
#include "methods/yu_point_ekf/yu_point_ekf.h"
#include "common/json_changes.h"

namespace slt {
namespace {

// The default rectified rig, and one with a rotated right camera, a baseline off the x axis
// and different intrinsics (epipolar lines neither horizontal nor parallel).
StereoRig Rig(bool general) {
  StereoRig rig;
  if (!general) return rig;
  rig.right.fx = 790.0;
  rig.right.fy = 805.0;
  rig.right.cx = 330.0;
  rig.right.cy = 228.0;
  rig.right_from_left = Rigid3d(ExpSO3(Eigen::Vector3d(0.03, -0.05, 0.04)), Eigen::Vector3d(-0.1, 0.012, 0.006));
  return rig;
}

Segment2d Reversed(const Segment2d& s) { return (Segment2d() << s.tail<2>(), s.head<2>()).finished(); }

class PointTransferModelTest : public ::testing::TestWithParam<bool> {
 protected:
  TinyScene Scene() const {
    TinyScene scene;
    scene.rig = Rig(GetParam());
    return scene;
  }
};

TEST_P(PointTransferModelTest, ZeroResidualAtTruthAndJacobianMatches) {
  const TinyScene scene = Scene();
  PointTransferModel model(PointTransferOptions{});
  model.Reset(scene.rig);
  const Rigid3d truth = SomeMotion();
  ASSERT_EQ(model.SetReference(scene.Frame(Rigid3d())), 8);
  ASSERT_EQ(model.SetCurrent(scene.Frame(truth)), 8);
  EXPECT_EQ(model.CurrentStereoFeatures(), 8);
  for (int i = 0; i < model.NumFeatures(); ++i) {
    FeatureBlock block;
    ASSERT_TRUE(model.Evaluate(i, truth, true, &block));
    EXPECT_LT(block.residual.norm(), 1e-9) << "feature " << i;
    for (const Rigid3d& at : {truth, NearTruth(truth)}) {
      ASSERT_TRUE(model.Evaluate(i, at, false, &block));
      const auto f = [&](const Vector6d& d) -> Eigen::Vector4d {
        FeatureBlock b;
        EXPECT_TRUE(model.Evaluate(i, ExpSE3(d) * at, false, &b));
        return b.residual;
      };
      const Eigen::Matrix<double, 4, 6> numeric = CentralDifferenceJacobian<4, 6>(f, Vector6d::Zero());
      EXPECT_LT((numeric - block.jacobian).norm(), 1e-6 * (1.0 + numeric.norm())) << "feature " << i;
    }
  }
  // Away from the truth the residual is not zero (the test above can fail).
  FeatureBlock block;
  ASSERT_TRUE(model.Evaluate(0, NearTruth(truth), false, &block));
  EXPECT_GT(block.residual.norm(), 0.5);
}

TEST_P(PointTransferModelTest, PlaneFormEqualsTensorPointTransfer) {
  const TinyScene scene = Scene();
  const StereoRig& rig = scene.rig;
  PointTransferModel model(PointTransferOptions{});
  model.Reset(rig);
  const Rigid3d truth = SomeMotion();
  const StereoFrame ref = scene.Frame(Rigid3d()), cur = scene.Frame(truth);
  model.SetReference(ref);
  model.SetCurrent(cur);
  const Rigid3d at = NearTruth(truth);  // any pose: the transfer is an identity in M
  const Matrix34d E = rig.right_from_left.ToMatrix3x4();
  const TrifocalTensor into_left = TrifocalTensorFromCameras(E, at.ToMatrix3x4());
  const TrifocalTensor into_right = TrifocalTensorFromCameras(E, (rig.right_from_left * at).ToMatrix3x4());
  const Eigen::Matrix3d k_left = rig.left.K(), k_right = rig.right.K();
  for (int i = 0; i < model.NumFeatures(); ++i) {
    const int line = (model.FeatureId(i) - 10) / 3, k = model.FeatureEndpoint(i);
    const Eigen::Vector2d x = ref.left[line].segment.segment<2>(2 * k);
    const Eigen::Vector2d x2 = ref.right[line].segment.segment<2>(2 * k);
    const Eigen::Vector3d xn = k_left.inverse() * Homogeneous(x);
    // The epipolar line of x in I'_1 (normalised), through the images of two points of its ray.
    const Eigen::Vector3d p1 = rig.right_from_left * (0.3 * xn), p2 = rig.right_from_left * (2.0 * xn);
    const Eigen::Vector3d epipolar = (p1 / p1.z()).cross(p2 / p2.z());
    // Perpendicular in pixels through x', back to normalised coordinates.
    const Eigen::Vector3d line2 =
        k_right.transpose() * PerpendicularLineThroughPoint(k_right.inverse().transpose() * epipolar, x2);
    EXPECT_LT(line2.normalized().cross(model.geometry().TransferLine(x, x2).normalized()).norm(), 1e-9);
    // The epipolar line itself transfers nothing: its plane contains the ray of x.
    EXPECT_LT(TransferPoint(into_left, xn, epipolar.normalized()).norm(), 1e-12);

    const Eigen::Vector3d yl = k_left * TransferPoint(into_left, xn, line2);
    const Eigen::Vector3d yr = k_right * TransferPoint(into_right, xn, line2);
    FeatureBlock block;
    ASSERT_TRUE(model.Evaluate(i, at, false, &block));
    Eigen::Vector4d expected;
    expected << cur.left[line].segment.segment<2>(2 * k) - yl.head<2>() / yl.z(),
        cur.right[line].segment.segment<2>(2 * k) - yr.head<2>() / yr.z();
    EXPECT_LT((expected - block.residual).norm(), 1e-9) << "feature " << i;
  }
}

TEST_P(PointTransferModelTest, PropagatedCovarianceMatchesNumericNoiseJacobian) {
  const TinyScene scene = Scene();
  PointTransferOptions options;
  options.endpoint_sigma_px = 1.3;
  options.covariance_floor_px = 0.07;
  const Rigid3d truth = SomeMotion();
  StereoFrame ref = scene.Frame(Rigid3d());
  const StereoFrame cur = scene.Frame(truth);
  // Noisy reference points: x' off the epipolar line of x, where x also moves the transfer
  // through the epipolar line (on exact data that path has zero derivative).
  ref.left[1].segment += Segment2d(0.8, -1.1, 1.4, 0.6);
  ref.right[1].segment += Segment2d(-1.5, 2.0, 1.2, -1.7);
  ref.right[2].segment += Segment2d(1.0, 1.8, -2.2, 1.3);
  const Rigid3d at = NearTruth(truth);
  for (const int feature : {2, 5}) {
    const int line = feature / 2, k = feature % 2;
    PointTransferModel model(options);
    model.Reset(scene.rig);
    model.SetReference(ref);
    model.SetCurrent(cur);
    ASSERT_EQ(model.FeatureId(feature), 10 + 3 * line);
    ASSERT_EQ(model.FeatureEndpoint(feature), k);
    FeatureBlock block;
    ASSERT_TRUE(model.Evaluate(feature, at, true, &block));
    // Perturb the 8 pixel coordinates of the feature's point: x, x', y, y'.
    const auto residual_of = [&](const Eigen::Matrix<double, 8, 1>& p) -> Eigen::Vector4d {
      StereoFrame r = ref, c = cur;
      r.left[line].segment.segment<2>(2 * k) = p.segment<2>(0);
      r.right[line].segment.segment<2>(2 * k) = p.segment<2>(2);
      c.left[line].segment.segment<2>(2 * k) = p.segment<2>(4);
      c.right[line].segment.segment<2>(2 * k) = p.segment<2>(6);
      FeatureBlock b;
      EXPECT_TRUE(EvaluateOnFrames<PointTransferModel>(options, scene.rig, r, c, feature, at, false, &b));
      return b.residual;
    };
    Eigen::Matrix<double, 8, 1> p;
    p << ref.left[line].segment.segment<2>(2 * k), ref.right[line].segment.segment<2>(2 * k),
        cur.left[line].segment.segment<2>(2 * k), cur.right[line].segment.segment<2>(2 * k);
    const Eigen::Matrix<double, 4, 8> N = CentralDifferenceJacobian<4, 8>(residual_of, p, 1e-5);
    // x' moves the transfer (through l'): the reference columns are not all zero.
    EXPECT_GT((N.block<4, 2>(0, 2).norm()), 0.1);
    Eigen::Matrix4d expected = 1.3 * 1.3 * N * N.transpose();
    expected.diagonal().array() += 0.07 * 0.07;
    EXPECT_LT((expected - block.covariance).norm(), 1e-6 * expected.norm()) << "feature " << feature;
  }
}

TEST_P(PointTransferModelTest, EndpointOrderDoesNotMatter) {
  const TinyScene scene = Scene();
  PointTransferModel model(PointTransferOptions{});
  model.Reset(scene.rig);
  const Rigid3d truth = SomeMotion();
  StereoFrame ref = scene.Frame(Rigid3d()), cur = scene.Frame(truth);
  // As a detector may: right segments reversed in the reference, left ones in the current frame,
  // both in another line.
  const StereoFrame ref_in_order = ref;
  for (int line : {0, 2}) ref.right[line].segment = Reversed(ref.right[line].segment);
  for (int line : {1, 2}) cur.left[line].segment = Reversed(cur.left[line].segment);
  cur.right[3].segment = Reversed(cur.right[3].segment);
  cur.left[3].segment = Reversed(cur.left[3].segment);
  ASSERT_EQ(model.SetReference(ref), 8);
  ASSERT_EQ(model.SetCurrent(cur), 8);
  for (int i = 0; i < model.NumFeatures(); ++i) {
    FeatureBlock block;
    ASSERT_TRUE(model.Evaluate(i, truth, true, &block));
    EXPECT_LT(block.residual.norm(), 1e-9) << "feature " << i;
  }
  // Feature (line, k) is endpoint k of the reference left segment, whatever the other orders.
  for (int i = 0; i < model.NumFeatures(); ++i) {
    EXPECT_EQ(model.FeatureId(i), 10 + 3 * (i / 2));
    EXPECT_EQ(model.FeatureEndpoint(i), i % 2);
  }
  // With endpoint_pairing "given" the observed order is trusted: a line whose current left
  // segment is reversed no longer fits the truth, the others still do.
  PointTransferOptions given;
  given.endpoint_pairing = EndpointPairing::kGiven;
  PointTransferModel trusting(given);
  trusting.Reset(scene.rig);
  StereoFrame cur_one_reversed = scene.Frame(truth);
  cur_one_reversed.left[1].segment = Reversed(cur_one_reversed.left[1].segment);
  ASSERT_EQ(trusting.SetReference(ref_in_order), 8);
  ASSERT_EQ(trusting.SetCurrent(cur_one_reversed), 8);
  for (int i = 0; i < trusting.NumFeatures(); ++i) {
    FeatureBlock block;
    ASSERT_TRUE(trusting.Evaluate(i, truth, false, &block));
    EXPECT_EQ(block.residual.norm() > 1.0, trusting.FeatureId(i) == 13) << "feature " << i;
  }
  // The rules on their own.
  for (int line = 0; line < 4; ++line) {
    const Segment2d& l = ref_in_order.left[line].segment;
    const Segment2d& r = ref_in_order.right[line].segment;
    EXPECT_FALSE(StereoEndpointsSwapped(model.geometry(), l, r, 1.0)) << "line " << line;
    EXPECT_TRUE(StereoEndpointsSwapped(model.geometry(), l, Reversed(r), 1.0)) << "line " << line;
  }
}

INSTANTIATE_TEST_SUITE_P(RectifiedAndGeneralRig, PointTransferModelTest, ::testing::Values(false, true));

TEST(PointTransferModel, PairingAlongTheEpipolarLinesFollowsTheDirection) {
  // A horizontal segment in the rectified rig: both pairings have (almost) zero epipolar
  // distance, the directions decide.
  TinyScene scene;
  scene.lines = {{{-0.10, 0.02, 0.50}, {0.10, 0.02, 0.50}}};
  const StereoFrame f = scene.Frame(Rigid3d());
  const StereoPointGeometry geometry(scene.rig);
  const Segment2d l = f.left[0].segment, r = f.right[0].segment;
  EXPECT_LT(std::abs(geometry.EpipolarDistance(l.head<2>(), r.tail<2>()) -
                     geometry.EpipolarDistance(l.head<2>(), r.head<2>())),
            1e-9);
  EXPECT_FALSE(StereoEndpointsSwapped(geometry, l, r, 1.0));
  EXPECT_TRUE(StereoEndpointsSwapped(geometry, l, Reversed(r), 1.0));
  // A slanted one whose epipolar distances are clear: they win over the direction test, which
  // a right segment whose endpoints were drawn reversed and shifted would mislead.
  scene.lines = {{{-0.05, -0.08, 0.50}, {0.03, 0.08, 0.55}}};
  const StereoFrame g = scene.Frame(Rigid3d());
  EXPECT_FALSE(StereoEndpointsSwapped(geometry, g.left[0].segment, g.right[0].segment, 1.0));
  EXPECT_TRUE(StereoEndpointsSwapped(geometry, g.left[0].segment, Reversed(g.right[0].segment), 1.0));
}

TEST(PointTransferModel, TemporalPairingSurvivesLargeMotionAlongTheLine) {
  // A 40 px segment moved 100 px along itself and turned by 10 deg: the nearest-endpoint rule
  // would swap, the direction rule does not.
  const Segment2d reference(100.0, 200.0, 140.0, 200.0);
  const double c = std::cos(10.0 * M_PI / 180.0), s = std::sin(10.0 * M_PI / 180.0);
  const Segment2d current(200.0, 200.0, 200.0 + 40.0 * c, 200.0 + 40.0 * s);
  EXPECT_LT((current.head<2>() - reference.tail<2>()).norm(), (current.head<2>() - reference.head<2>()).norm());
  EXPECT_FALSE(TemporalEndpointsSwapped(reference, current));
  EXPECT_TRUE(TemporalEndpointsSwapped(reference, Reversed(current)));
}

TEST(PointTransferModel, DegeneratePointsAreNotFeatures) {
  TinyScene scene;
  // Line 0 from 0.5 m to 100 m away (its far endpoint has a disparity below 1 px); line 1 fine.
  scene.lines = {{{0.0, 0.05, 0.5}, {10.0, 0.05, 100.0}}, {{0.05, -0.12, 0.45}, {0.02, 0.14, 0.55}}};
  PointTransferModel model(PointTransferOptions{});
  model.Reset(scene.rig);
  EXPECT_EQ(model.SetReference(scene.Frame(Rigid3d())), 3);
  EXPECT_EQ(model.SetCurrent(scene.Frame(Rigid3d())), 3);
  EXPECT_EQ(model.FeatureId(0), 10);
  EXPECT_EQ(model.FeatureEndpoint(0), 0);
  EXPECT_EQ(model.FeatureId(1), 13);
  // With the threshold off, the far point is a feature.
  PointTransferOptions o;
  o.min_ray_plane_angle_deg = 0.0;
  PointTransferModel lax(o);
  lax.Reset(scene.rig);
  EXPECT_EQ(lax.SetReference(scene.Frame(Rigid3d())), 4);

  // A point behind the current camera at the evaluated pose is not measured there.
  FeatureBlock block;
  ASSERT_TRUE(model.Evaluate(1, Rigid3d(), true, &block));
  const Rigid3d behind(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.0, 0.0, -0.6));
  EXPECT_FALSE(model.Evaluate(1, behind, true, &block));
  // Negative disparity (a stereo match that puts the point behind the camera).
  StereoFrame f = scene.Frame(Rigid3d());
  f.right[1].segment(0) = f.left[1].segment(0) + 30.0;
  EXPECT_EQ(model.SetReference(f), 2);
}

TEST(PointTransferModel, FixedNoiseIsDiagonal) {
  TinyScene scene;
  PointTransferOptions o;
  o.noise = MeasurementNoise::kFixed;
  o.fixed_sigma_px = 1.7;
  PointTransferModel model(o);
  model.Reset(scene.rig);
  model.SetReference(scene.Frame(Rigid3d()));
  model.SetCurrent(scene.Frame(SomeMotion()));
  FeatureBlock block;
  ASSERT_TRUE(model.Evaluate(3, SomeMotion(), true, &block));
  EXPECT_LT((block.covariance - 1.7 * 1.7 * Eigen::Matrix4d::Identity()).norm(), 1e-12);
}

TEST(PointTransferModel, SkipsMonocularAndShortSegments) {
  TinyScene scene;
  PointTransferModel model(PointTransferOptions{});
  StereoFrame ref = scene.Frame(Rigid3d()), cur = scene.Frame(SomeMotion());
  ref.right.erase(ref.right.begin());                          // line 10: left only
  cur.left[2].segment << 100.0, 100.0, 102.0, 101.0;          // line 16: too short now
  std::reverse(cur.right.begin(), cur.right.end());            // order of observations is free
  // Two endpoints per line.
  EXPECT_EQ(Associate(model, scene.rig, ref, cur), (Association{6, 4, 6, {13, 13, 19, 19}}));
}

TEST(PointTransferModel, OptionErrorsNameTheKey) {
  const auto read = [](const char* text) {
    return ConfigErrorOf([&] {
      const auto j = nlohmann::json::parse(text);
      JsonReader r(j, "cfg.json", "measurement");
      PointTransferOptions o;
      ReadPointTransferOptions(r, &o);
    });
  };
  EXPECT_NE(read(R"({"noise": "gaussian"})").find("cfg.json: key 'measurement.noise'"), std::string::npos);
  EXPECT_NE(read(R"({"endpoint_pairing": "nearest"})").find("key 'measurement.endpoint_pairing'"), std::string::npos);
  EXPECT_NE(read(R"({"min_depth_m": 0})").find("key 'measurement.min_depth_m'"), std::string::npos);
  EXPECT_NE(read(R"({"min_ray_plane_angle_deg": 90})").find("key 'measurement.min_ray_plane_angle_deg'"),
            std::string::npos);
  EXPECT_NE(read(R"({"endpoint_sigma_px": "1"})").find("key 'measurement.endpoint_sigma_px'"), std::string::npos);
  EXPECT_EQ(read(R"({"noise": "fixed", "fixed_sigma_px": 1.0})"), "");

  const auto create = [](const char* text) {
    return ConfigErrorOf([&] { YuPointEkfInfo().create(nlohmann::json::parse(text), "cfg.json"); });
  };
  EXPECT_NE(create(R"({"preset": "yu"})").find("cfg.json: key 'preset'"), std::string::npos);
  EXPECT_NE(create(R"({"measurement": {"sigma": 1}})").find("key 'measurement.sigma'"), std::string::npos);
  EXPECT_NE(create(R"({"filter": {"max_iterations": 0}})").find("key 'filter.max_iterations'"), std::string::npos);
  EXPECT_EQ(create(R"({"preset": "paper"})"), "");
}

TEST(YuPointEkf, PresetsAndEcho) {
  const auto paper = YuPointEkfInfo().create({{"preset", "paper"}}, "test")->Options();
  EXPECT_EQ(paper["filter"]["state"], "velocity");
  EXPECT_EQ(paper["filter"]["max_iterations"], 1);
  EXPECT_EQ(paper["filter"]["robust"], false);
  EXPECT_EQ(paper["filter"]["adaptive_noise"], false);
  EXPECT_EQ(paper["measurement"]["noise"], "fixed");
  const auto overridden =
      YuPointEkfInfo().create({{"preset", "paper"}, {"measurement", {{"noise", "propagated"}}}}, "test")->Options();
  EXPECT_EQ(overridden["measurement"]["noise"], "propagated");
  const auto defaults = YuPointEkfInfo().create(nlohmann::json::object(), "test")->Options();
  EXPECT_EQ(defaults["measurement"], PointTransferOptionsToJson(PointTransferOptions{}));
  EXPECT_EQ(defaults["filter"]["state"], "pose_velocity");
}

TEST(YuPointEkf, TracksATinySceneExactly) {
  // Four lines (eight points), a constant motion, exact data: every point used on every frame,
  // and the pose exact once the noise scale has adapted (it starts at the nominal noise, so the
  // first frames lean on the motion prior).
  TinyScene scene;
  auto tracker = YuPointEkfInfo().create(nlohmann::json::object(), "test");
  tracker->Reset(scene.rig);
  Vector6d xi;
  xi << 0.002, -0.001, 0.0015, 0.002, -0.003, 0.001;
  Rigid3d truth;
  const int frames = 40;
  for (int k = 0; k < frames; ++k) {
    const TrackerOutput out = tracker->Track(scene.Frame(truth));
    ASSERT_LT((out.cam_from_world.ToMatrix4() - truth.ToMatrix4()).norm(), k < 10 ? 1e-3 : 1e-6) << "frame " << k;
    if (k > 0) {
      EXPECT_EQ(out.features_used, 8) << "frame " << k;
    }
    truth = ExpSE3(xi) * truth;
  }
}

}  // namespace
}  // namespace slt
