#include "methods/trifocal_line_ekf/line_transfer_model.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "geometry/numeric_jacobian.h"
#include "geometry/se3.h"
#include "methods/stereo_ekf/tiny_scene.h"

namespace slt {
namespace {

// Central differences of feature `feature`'s residual under at <- Exp(d) at.
Eigen::Matrix<double, 4, 6> NumericPoseJacobian(const LineTransferModel& model, int feature, const Rigid3d& at) {
  const auto f = [&](const Vector6d& d) -> Eigen::Vector4d {
    FeatureBlock b;
    EXPECT_TRUE(model.Evaluate(feature, ExpSE3(d) * at, false, &b));
    return b.residual;
  };
  return CentralDifferenceJacobian<4, 6>(f, Vector6d::Zero());
}

// The options with these modes (their JSON names), no epipolar gate.
LineTransferOptions Options(const std::string& direction, const std::string& residual,
                            const std::string& noise = "propagated") {
  LineTransferOptions o;
  JsonReader reader(nlohmann::json{{"direction", direction}, {"residual", residual}, {"noise", noise}}, "test");
  ReadLineTransferOptions(reader, &o);
  o.epipolar.min_epipolar_angle_deg = 0.0;
  return o;
}

// Central differences of feature `feature`'s residual at `at` with respect to the 16 endpoint
// coordinates of its four segments: [reference left | reference right | current left | current
// right].
Eigen::Matrix<double, 4, 16> NumericNoiseJacobian(const LineTransferOptions& options, const StereoRig& rig,
                                                  const StereoFrame& ref, const StereoFrame& cur, int feature,
                                                  const Rigid3d& at) {
  const auto residual_of = [&](const Eigen::Matrix<double, 16, 1>& x) -> Eigen::Vector4d {
    StereoFrame r = ref, c = cur;
    r.left[feature].segment = x.segment<4>(0);
    r.right[feature].segment = x.segment<4>(4);
    c.left[feature].segment = x.segment<4>(8);
    c.right[feature].segment = x.segment<4>(12);
    FeatureBlock b;
    EXPECT_TRUE(EvaluateOnFrames<LineTransferModel>(options, rig, r, c, feature, at, false, &b));
    return b.residual;
  };
  Eigen::Matrix<double, 16, 1> x;
  x << ref.left[feature].segment, ref.right[feature].segment, cur.left[feature].segment, cur.right[feature].segment;
  return CentralDifferenceJacobian<4, 16>(residual_of, x, 1e-5);
}

class LineTransferModelTest : public ::testing::TestWithParam<std::tuple<std::string, std::string>> {};

TEST_P(LineTransferModelTest, ZeroResidualAtTruthAndJacobianMatches) {
  const auto [direction, residual] = GetParam();
  TinyScene scene;
  LineTransferModel model(Options(direction, residual));
  model.Reset(scene.rig);
  const Rigid3d truth = SomeMotion();
  ASSERT_EQ(model.SetReference(scene.Frame(Rigid3d())), 4);
  ASSERT_EQ(model.SetCurrent(scene.Frame(truth)), 4);
  for (int i = 0; i < model.NumFeatures(); ++i) {
    FeatureBlock block;
    ASSERT_TRUE(model.Evaluate(i, truth, true, &block));
    EXPECT_LT(block.residual.norm(), 1e-9) << "feature " << i;
    // Jacobian against central differences, away from the truth too.
    const Rigid3d at = NearTruth(truth);
    ASSERT_TRUE(model.Evaluate(i, at, false, &block));
    // Negative control: away from the truth the residual and the Jacobian do not vanish (a model
    // returning zeros would pass the two checks around this one).
    EXPECT_GT(block.residual.norm(), 1e-3) << "feature " << i;
    EXPECT_GT(block.jacobian.norm(), 1.0) << "feature " << i;
    const Eigen::Matrix<double, 4, 6> numeric = NumericPoseJacobian(model, i, at);
    EXPECT_LT((numeric - block.jacobian).norm(), 1e-6 * (1.0 + numeric.norm())) << "feature " << i;
  }
}

TEST_P(LineTransferModelTest, PropagatedCovarianceMatchesNumericNoiseJacobian) {
  const auto [direction, residual] = GetParam();
  TinyScene scene;
  LineTransferOptions options = Options(direction, residual);
  options.endpoint_sigma_px = 1.3;
  const Rigid3d truth = SomeMotion();
  const StereoFrame ref = scene.Frame(Rigid3d()), cur = scene.Frame(truth);
  const int feature = 1;
  FeatureBlock block;
  ASSERT_TRUE(EvaluateOnFrames<LineTransferModel>(options, scene.rig, ref, cur, feature, truth, true, &block));
  const Eigen::Matrix<double, 4, 16> N = NumericNoiseJacobian(options, scene.rig, ref, cur, feature, truth);
  Eigen::Matrix4d expected = 1.3 * 1.3 * N * N.transpose();
  const bool distance = residual == "endpoint_distance";
  const Eigen::Vector4d floor = distance ? Eigen::Vector4d::Constant(0.05)
                                         : Eigen::Vector4d(1e-4, 0.05, 1e-4, 0.05);
  expected.diagonal() += floor.array().square().matrix();
  EXPECT_LT((expected - block.covariance).norm(), 1e-6 * expected.norm());
}

// The structure Jacobian G (consider_structure) is sigma times the reference endpoints' columns
// of the noise Jacobian, so that R = R_current + G G^T.
TEST(LineTransferModel, StructureJacobianIsTheReferenceEndpointsPartOfTheNoise) {
  TinyScene scene;
  LineTransferOptions options = Options("reference_to_current", "endpoint_distance");
  options.endpoint_sigma_px = 1.3;
  options.consider_structure = true;
  const Rigid3d truth = SomeMotion();
  const StereoFrame ref = scene.Frame(Rigid3d()), cur = scene.Frame(truth);
  const int feature = 1;
  LineTransferModel model(options);
  model.Reset(scene.rig);
  ASSERT_EQ(model.SetReference(ref), 4);
  ASSERT_EQ(model.SetCurrent(cur), 4);
  ASSERT_TRUE(model.DescribesStructure());
  EXPECT_EQ(model.NumStructures(), 4);
  EXPECT_EQ(model.StructureOf(feature), feature);
  FeatureModel::StructureJacobian g;
  ASSERT_TRUE(model.EvaluateStructureJacobian(feature, truth, &g));
  const Eigen::Matrix<double, 4, 8> expected =
      1.3 * NumericNoiseJacobian(options, scene.rig, ref, cur, feature, truth).leftCols<8>();
  EXPECT_GT(expected.norm(), 0.1);
  EXPECT_LT((expected - g).norm(), 1e-6 * expected.norm());
  // What is left of R is positive definite: the current segments' noise and the floor.
  FeatureBlock block;
  ASSERT_TRUE(model.Evaluate(feature, truth, true, &block));
  const Eigen::Matrix4d current = block.covariance - g * g.transpose();
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(current).eigenvalues()(0), 0.04 * 0.04);
  options.consider_structure = false;
  EXPECT_FALSE(LineTransferModel(options).DescribesStructure());
}

TEST(LineTransferModel, ConsiderStructureNeedsTheReferenceToCurrentDirectionAndPropagatedNoise) {
  LineTransferOptions options;
  options.consider_structure = true;
  EXPECT_NO_THROW(options.Check());
  options.direction = TransferDirection::kCurrentToReference;
  EXPECT_THROW(options.Check(), ConfigError);
  options.direction = TransferDirection::kReferenceToCurrent;
  options.noise = MeasurementNoise::kFixed;
  EXPECT_THROW(options.Check(), ConfigError);
}

INSTANTIATE_TEST_SUITE_P(AllVariants, LineTransferModelTest,
                         ::testing::Combine(::testing::Values("current_to_reference", "reference_to_current"),
                                            ::testing::Values("endpoint_distance", "theta_lambda")));

TEST(LineTransferModel, EndpointDistancesAreEvaluatesResidual) {
  TinyScene scene;
  const Rigid3d truth = SomeMotion(), at = NearTruth(truth);
  for (const char* direction : {"reference_to_current", "current_to_reference"}) {
    for (const char* residual : {"endpoint_distance", "theta_lambda"}) {
      LineTransferModel model(Options(direction, residual));
      model.Reset(scene.rig);
      model.SetReference(scene.Frame(Rigid3d()));
      ASSERT_EQ(model.SetCurrent(scene.Frame(truth)), 4);
      const bool supported = std::string(direction) == "reference_to_current" && std::string(residual) == "endpoint_distance";
      for (int i = 0; i < model.NumFeatures(); ++i) {
        Eigen::Vector4d distances;
        ASSERT_EQ(model.EndpointDistances(i, at, &distances), supported) << direction << " " << residual;
        if (!supported) continue;
        FeatureBlock block;
        ASSERT_TRUE(model.Evaluate(i, at, false, &block));
        EXPECT_GT(block.residual.norm(), 1e-3);
        EXPECT_LT((distances - block.residual).norm(), 1e-12 * block.residual.norm()) << "feature " << i;
      }
    }
  }
}

TEST(LineTransferModel, AssociatesByIdAndSkipsMonocularLines) {
  TinyScene scene;
  LineTransferModel model(Options("current_to_reference", "endpoint_distance"));
  StereoFrame ref = scene.Frame(Rigid3d());
  StereoFrame cur = scene.Frame(SomeMotion());
  ref.right.erase(ref.right.begin());          // line 10: left only in the reference
  cur.left.erase(cur.left.begin() + 2);        // line 16: right only in the current frame
  std::reverse(cur.left.begin(), cur.left.end());  // order does not matter
  EXPECT_EQ(Associate(model, scene.rig, ref, cur), (Association{3, 2, 3, {13, 19}}));
}

TEST(LineTransferModel, GatesLinesInTheEpipolarPlane) {
  TinyScene scene;
  scene.lines = {{{-0.1, 0.02, 0.5}, {0.1, 0.02, 0.5}}};  // horizontal: in the rig's epipolar plane
  LineTransferOptions o = Options("current_to_reference", "endpoint_distance");
  o.epipolar.min_epipolar_angle_deg = 1.0;
  LineTransferModel model(o);
  model.Reset(scene.rig);
  EXPECT_EQ(model.SetReference(scene.Frame(Rigid3d())), 0);  // not measurable
  model.SetCurrent(scene.Frame(Rigid3d()));
  FeatureBlock block;
  EXPECT_FALSE(model.Evaluate(0, Rigid3d(), true, &block));

  // The same line tilted by 2 deg in the image passes a 1 deg gate, and fails a 3 deg one.
  const double dy = 0.1 * std::tan(2.0 * M_PI / 180.0);
  scene.lines = {{{-0.1, 0.02 - dy, 0.5}, {0.1, 0.02 + dy, 0.5}}};
  LineTransferModel tilted(o);
  tilted.Reset(scene.rig);
  EXPECT_EQ(tilted.SetReference(scene.Frame(Rigid3d())), 1);
  tilted.SetCurrent(scene.Frame(SomeMotion()));
  EXPECT_TRUE(tilted.Evaluate(0, SomeMotion(), true, &block));
  EXPECT_LT(block.residual.norm(), 1e-6);
  o.epipolar.min_epipolar_angle_deg = 3.0;
  LineTransferModel strict(o);
  strict.Reset(scene.rig);
  EXPECT_EQ(strict.SetReference(scene.Frame(Rigid3d())), 0);
}

// A line in the rig's epipolar plane (horizontal) is not measured by the transfer; with
// endpoint_placement_sigma_px it is placed by its endpoints' disparities, measured exactly at the
// truth, and it measures the vertical translation, which the transfer's lines of a wall of
// vertical edges do not. Its covariance is the endpoints' (sigma along each segment, sigma across)
// carried through the placement: checked against central differences of the residual in the
// reference endpoints, through the consider parameters' Jacobian G (G G^T = N Sigma N^T).
TEST(LineTransferModel, PlacesLinesInTheEpipolarPlaneByTheirEndpoints) {
  TinyScene scene;
  scene.lines = {{{-0.1, 0.02, 0.5}, {0.12, 0.02, 0.55}}};  // horizontal, receding
  LineTransferOptions o = Options("reference_to_current", "endpoint_distance");
  o.epipolar.min_epipolar_angle_deg = 1.0;
  o.endpoint_sigma_px = 0.4;
  const StereoFrame ref = scene.Frame(Rigid3d()), cur = scene.Frame(SomeMotion());
  {
    LineTransferModel off(o);
    off.Reset(scene.rig);
    EXPECT_EQ(off.SetReference(ref), 0);
  }
  o.endpoint_placement_sigma_px = 2.0;
  o.consider_structure = true;
  LineTransferModel model(o);
  model.Reset(scene.rig);
  ASSERT_EQ(model.SetReference(ref), 1);
  ASSERT_EQ(model.SetCurrent(cur), 1);
  // A frame's lines placed by their endpoints are not what a new reference is taken for.
  EXPECT_EQ(model.CurrentStereoFeatures(), 0);
  FeatureBlock block;
  ASSERT_TRUE(model.Evaluate(0, SomeMotion(), true, &block));
  EXPECT_LT(block.residual.norm(), 1e-9);
  // 1 mm of vertical translation moves the line by about f * 1 mm / 0.5 m in both images.
  Vector6d up = Vector6d::Zero();
  up(1) = 0.001;
  ASSERT_TRUE(model.Evaluate(0, ExpSE3(up) * SomeMotion(), false, &block));
  EXPECT_GT(block.residual.cwiseAbs().minCoeff(), 0.5 * scene.rig.left.fy * 0.001 / 0.55);

  FeatureModel::StructureJacobian g;
  ASSERT_TRUE(model.EvaluateStructureJacobian(0, SomeMotion(), &g));
  const Eigen::Matrix<double, 4, 8> n = NumericNoiseJacobian(o, scene.rig, ref, cur, 0, SomeMotion()).leftCols<8>();
  Eigen::Matrix<double, 8, 8> sigma = Eigen::Matrix<double, 8, 8>::Zero();
  for (int k = 0; k < 4; ++k) {
    const Segment2d& segment = k < 2 ? ref.left[0].segment : ref.right[0].segment;
    const Eigen::Vector2d t = (segment.tail<2>() - segment.head<2>()).normalized(), m(-t.y(), t.x());
    sigma.block<2, 2>(2 * k, 2 * k) = 2.0 * 2.0 * t * t.transpose() + 0.4 * 0.4 * m * m.transpose();
  }
  const Eigen::Matrix4d expected = n * sigma * n.transpose();
  EXPECT_GT(expected.norm(), 1e-3);
  EXPECT_LT((g * g.transpose() - expected).norm(), 1e-5 * expected.norm());

  // Only with the direction and noise that measure a line by its projection.
  o.direction = TransferDirection::kCurrentToReference;
  o.consider_structure = false;
  EXPECT_THROW(o.Check(), ConfigError);
}

// A short segment passes the angle gate on its noisy angle alone; the extent gate measures how
// many pixels it spans across the epipolar lines (length x sine of the angle).
TEST(LineTransferModel, GatesShortLinesByTheirExtentAcrossEpipolarLines) {
  TinyScene scene;
  const double dy = 0.01 * std::tan(10.0 * M_PI / 180.0);  // 2 cm long, 10 deg from horizontal
  scene.lines = {{{-0.01, 0.02 - dy, 0.5}, {0.01, 0.02 + dy, 0.5}}};
  const StereoFrame frame = scene.Frame(Rigid3d());
  ASSERT_EQ(frame.left.size(), 1u);
  const Segment2d& s = frame.left[0].segment;
  const double extent_px = std::abs(s(3) - s(1));  // a horizontal rig: rows
  ASSERT_GT(extent_px, 2.0);
  LineTransferOptions o = Options("reference_to_current", "endpoint_distance");
  o.epipolar.min_epipolar_angle_deg = 3.0;
  for (const double gate : {0.0, extent_px - 0.5, extent_px + 0.5}) {
    o.min_epipolar_extent_px = gate;
    LineTransferModel model(o);
    model.Reset(scene.rig);
    EXPECT_EQ(model.SetReference(frame), gate < extent_px ? 1 : 0) << "gate " << gate << " px";
  }
}

// The paper's direction gates each transfer on its own (Sec. 4): when one degenerates the other
// still measures the line, in two rows of the block.
class OneTransferDegenerate : public ::testing::TestWithParam<std::string> {};

void ExpectOnlyRowsMeasured(const LineTransferModel& model, int feature, const Rigid3d& truth, unsigned rows) {
  FeatureBlock block;
  ASSERT_TRUE(model.Evaluate(feature, truth, true, &block));
  EXPECT_EQ(block.measured_rows, rows);
  EXPECT_EQ(block.Dimension(), 2);
  EXPECT_LT(block.residual.norm(), 1e-9);  // noise-free data at the truth
  // Away from the truth: the measured rows follow central differences and do not vanish; the
  // others carry nothing (zero residual and Jacobian, unit variance, no correlation).
  const Rigid3d at = NearTruth(truth);
  ASSERT_TRUE(model.Evaluate(feature, at, true, &block));
  ASSERT_EQ(block.measured_rows, rows);
  const Eigen::Matrix<double, 4, 6> numeric = NumericPoseJacobian(model, feature, at);
  EXPECT_LT((numeric - block.jacobian).norm(), 1e-6 * (1.0 + numeric.norm()));
  for (int row = 0; row < 4; ++row) {
    if (rows & (1u << row)) {
      EXPECT_GT(std::abs(block.residual(row)) + block.jacobian.row(row).norm(), 1e-3) << "row " << row;
      EXPECT_GT(block.covariance(row, row), 0.0);
    } else {
      EXPECT_EQ(block.residual(row), 0.0) << "row " << row;
      EXPECT_EQ(block.jacobian.row(row).norm(), 0.0) << "row " << row;
      Eigen::Vector4d unit = Eigen::Vector4d::Unit(row);
      EXPECT_EQ((block.covariance.row(row).transpose() - unit).norm(), 0.0) << "row " << row;
      EXPECT_EQ((block.covariance.col(row) - unit).norm(), 0.0) << "row " << row;
    }
  }
}

TEST_P(OneTransferDegenerate, CurrentLeftCameraAtTheReferenceRightCamera) {
  // T over (I_1, I'_1, I_t) then has two views with the same centre: every line lies in an
  // epipolar plane of them and T degenerates for all; T' (rows 2-3) still measures each line.
  TinyScene scene;
  LineTransferOptions options = Options("current_to_reference", "theta_lambda", GetParam());
  options.min_plane_angle_deg = 3.0;
  LineTransferModel model(options);
  model.Reset(scene.rig);
  const Rigid3d truth = scene.rig.right_from_left;
  ASSERT_EQ(model.SetReference(scene.Frame(Rigid3d())), 4);
  ASSERT_EQ(model.SetCurrent(scene.Frame(truth)), 4);
  for (int i = 0; i < model.NumFeatures(); ++i) {
    SCOPED_TRACE(i);
    ExpectOnlyRowsMeasured(model, i, truth, 0xCu);
  }
}

TEST_P(OneTransferDegenerate, LineHorizontalInTheCurrentPairOnly) {
  // Rolled by 30 deg, the current pair sees the line horizontal (in its epipolar plane): T'
  // (rows 2-3), which starts from the current pair, is out; T (reference right + current left)
  // still measures it.
  const Rigid3d truth = ExpSE3((Vector6d() << 0.01, -0.005, 0.0, 0.0, 0.0, 30.0 * M_PI / 180.0).finished());
  const Rigid3d ref_from_cam = truth.Inverse();
  TinyScene scene;
  scene.lines = {{ref_from_cam * Eigen::Vector3d(-0.1, 0.03, 0.5), ref_from_cam * Eigen::Vector3d(0.1, 0.03, 0.5)}};
  LineTransferOptions options = Options("current_to_reference", "theta_lambda", GetParam());
  options.epipolar.min_epipolar_angle_deg = 3.0;
  options.min_plane_angle_deg = 3.0;
  LineTransferModel model(options);
  model.Reset(scene.rig);
  ASSERT_EQ(model.SetReference(scene.Frame(Rigid3d())), 1);  // tilted by 30 deg there: measurable
  ASSERT_EQ(model.SetCurrent(scene.Frame(truth)), 1);
  ExpectOnlyRowsMeasured(model, 0, truth, 0x3u);
}

INSTANTIATE_TEST_SUITE_P(Noise, OneTransferDegenerate, ::testing::Values("fixed", "propagated"));

TEST(LineTransferModel, OptionErrorsNameTheKey) {
  const auto j = nlohmann::json::parse(R"({"residual": "angle"})");
  JsonReader r(j, "cfg.json", "measurement");
  LineTransferOptions o;
  try {
    ReadLineTransferOptions(r, &o);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("cfg.json: key 'measurement.residual'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace slt
