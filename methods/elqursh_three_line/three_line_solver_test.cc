#include "methods/elqursh_three_line/three_line_solver.h"

#include <gtest/gtest.h>

#include "methods/elqursh_three_line/three_line_test_data.h"

namespace slt {
namespace {

using namespace three_line_test;

// The candidate nearest to `truth` and its rotation error.
int NearestCandidate(const RotationCandidates& candidates, const Eigen::Matrix3d& truth, double* error) {
  int best = -1;
  *error = M_PI;
  for (int i = 0; i < candidates.count; ++i) {
    const double e = RotationAngle(candidates.b_from_a[i] * truth.transpose());
    if (e < *error) {
      *error = e;
      best = i;
    }
  }
  return best;
}

double BestCandidateError(const RotationCandidates& candidates, const Eigen::Matrix3d& truth) {
  double error;
  NearestCandidate(candidates, truth, &error);
  return error;
}

TEST(ThreeLineSolver, RotationAndTranslationExactOnNoiseFreeConfigurations) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const std::array<Line3, 3> lines = RandomPrimitiveConfiguration(rng);
    const Rigid3d b_from_a = RandomMotion(rng);
    RotationCandidates candidates;
    const PrimitiveConfigurationStatus status =
        RotationFromPrimitiveConfiguration(Images(Rigid3d(), lines), Images(b_from_a, lines), 1e-6, &candidates);
    ASSERT_EQ(status, PrimitiveConfigurationStatus::kValid) << "trial " << trial;
    ASSERT_EQ(candidates.count, 4);
    double rotation_error;
    const int best = NearestCandidate(candidates, b_from_a.rotation, &rotation_error);
    EXPECT_LT(rotation_error, 1e-9) << "trial " << trial;
    for (int i = 0; i < 4; ++i) {
      const Eigen::Matrix3d& r = candidates.b_from_a[i];
      EXPECT_LT((r * r.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
      EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
      for (int j = 0; j < i; ++j) EXPECT_GT(RotationAngle(r * candidates.b_from_a[j].transpose()), 0.1);
    }
    // The translation from the same three stereo lines with that rotation.
    std::array<StereoLineConstraint, 3> constraints;
    for (int i = 0; i < 3; ++i) constraints[i] = Constraint(b_from_a, lines[i]);
    // Row weights do not change an exact solution.
    constraints[1].left_normal *= 5.0;
    constraints[2].right_normal *= -0.2;
    Eigen::Vector3d t = Eigen::Vector3d::Constant(7.0);
    ASSERT_TRUE(TranslationFromStereoLines(candidates.b_from_a[best], kRightFromLeft, constraints.data(), 3, 1e-10, &t));
    EXPECT_LT((t - b_from_a.translation).norm(), 1e-12) << "trial " << trial;
  }
}

TEST(ThreeLineSolver, RotationDoesNotDependOnLineScaleOrSign) {
  std::mt19937_64 rng(8);
  const std::array<Line3, 3> lines = RandomPrimitiveConfiguration(rng);
  const Rigid3d b_from_a = RandomMotion(rng);
  PrimitiveConfigurationLines in_b = Images(b_from_a, lines);
  in_b.parallel1 *= -3.0;
  in_b.orthogonal *= 1e-3;
  RotationCandidates candidates;
  ASSERT_EQ(RotationFromPrimitiveConfiguration(Images(Rigid3d(), lines), in_b, 1e-6, &candidates),
            PrimitiveConfigurationStatus::kValid);
  EXPECT_LT(BestCandidateError(candidates, b_from_a.rotation), 1e-9);
}

TEST(ThreeLineSolver, CoincidentParallelLinesAreReported) {
  std::mt19937_64 rng(9);
  const std::array<Line3, 3> lines = RandomPrimitiveConfiguration(rng);
  PrimitiveConfigurationLines in_a = Images(Rigid3d(), lines);
  in_a.parallel2 = -2.0 * in_a.parallel1;
  RotationCandidates candidates;
  EXPECT_EQ(RotationFromPrimitiveConfiguration(in_a, Images(Rigid3d(), lines), 1e-6, &candidates),
            PrimitiveConfigurationStatus::kParallelLinesCoincide);
  EXPECT_EQ(candidates.count, 0);
  // In the second view too.
  EXPECT_EQ(RotationFromPrimitiveConfiguration(Images(Rigid3d(), lines), in_a, 1e-6, &candidates),
            PrimitiveConfigurationStatus::kParallelLinesCoincide);
  EXPECT_EQ(candidates.count, 0);
  // Two 3-D parallel lines in one plane with the camera centre: one image line.
  const Eigen::Vector3d d(1.0, 0.0, 0.0);
  const std::array<Line3, 3> coplanar = {Line3{{-0.1, 0.0, 0.5}, {0.1, 0.0, 0.5}}, Line3{{-0.1, 0.0, 0.8}, {0.1, 0.0, 0.8}},
                                         lines[2]};
  EXPECT_EQ(RotationFromPrimitiveConfiguration(Images(Rigid3d(), coplanar), Images(Rigid3d(), coplanar), 1e-6,
                                               &candidates),
            PrimitiveConfigurationStatus::kParallelLinesCoincide);
  EXPECT_EQ(candidates.count, 0);
}

TEST(ThreeLineSolver, ThirdParallelLineIsReportedNotAWrongRotation) {
  // Three parallel lines: the third image line passes through the vanishing point; taken as the
  // orthogonal line it would give a wrong rotation.
  std::mt19937_64 rng(10);
  for (int trial = 0; trial < 20; ++trial) {
    std::array<Line3, 3> lines = RandomPrimitiveConfiguration(rng);
    const Eigen::Vector3d d1 = lines[0].q - lines[0].p;
    lines[2].q = lines[2].p + d1;
    const Rigid3d b_from_a = RandomMotion(rng);
    RotationCandidates candidates;
    EXPECT_EQ(RotationFromPrimitiveConfiguration(Images(Rigid3d(), lines), Images(b_from_a, lines), 1e-6, &candidates),
              PrimitiveConfigurationStatus::kOrthogonalThroughVanishingPoint);
    EXPECT_EQ(candidates.count, 0);
  }
}

TEST(ThreeLineSolver, OrthogonalLineInThePlaneOrthogonalToTheVanishingDirectionIsReported) {
  // L3 orthogonal to D1 and in the plane through the camera centre orthogonal to D1: its image
  // is the vanishing line of that plane (n3 ~ d1) and says nothing about D2.
  std::mt19937_64 rng(11);
  std::array<Line3, 3> lines = RandomPrimitiveConfiguration(rng);
  const Eigen::Vector3d d1 = (lines[0].q - lines[0].p).normalized();
  const Eigen::Vector3d e = d1.cross(Eigen::Vector3d(0.0, 0.0, 1.0)).normalized();  // orthogonal to d1
  const Eigen::Vector3d f = d1.cross(e);                                                // orthogonal to both
  lines[2] = Line3{0.5 * e + 0.5 * f, 0.5 * e + 0.5 * f + 0.2 * (e - f).normalized()};
  PrimitiveConfigurationLines in_a = Images(Rigid3d(), lines);
  ASSERT_LT(in_a.orthogonal.normalized().cross(d1).norm(), 1e-12);
  RotationCandidates candidates;
  EXPECT_EQ(RotationFromPrimitiveConfiguration(in_a, Images(RandomMotion(rng), lines), 1e-6, &candidates),
            PrimitiveConfigurationStatus::kOrthogonalDirectionUndetermined);
  EXPECT_EQ(candidates.count, 0);
}

TEST(ThreeLineSolver, NonFiniteOrZeroLinesAreRejected) {
  std::mt19937_64 rng(12);
  const std::array<Line3, 3> lines = RandomPrimitiveConfiguration(rng);
  const PrimitiveConfigurationLines good = Images(Rigid3d(), lines);
  RotationCandidates candidates;
  PrimitiveConfigurationLines bad = good;
  bad.parallel1.setZero();
  EXPECT_NE(RotationFromPrimitiveConfiguration(bad, good, 1e-6, &candidates), PrimitiveConfigurationStatus::kValid);
  bad = good;
  bad.orthogonal.setZero();
  EXPECT_NE(RotationFromPrimitiveConfiguration(bad, good, 1e-6, &candidates), PrimitiveConfigurationStatus::kValid);
  bad = good;
  bad.orthogonal.x() = NAN;
  EXPECT_NE(RotationFromPrimitiveConfiguration(good, bad, 1e-6, &candidates), PrimitiveConfigurationStatus::kValid);
  EXPECT_EQ(candidates.count, 0);
}

TEST(ThreeLineSolver, TranslationFromRandomLinesAndAWrongRotationDisagree) {
  std::mt19937_64 rng(14);
  std::vector<StereoLineConstraint> constraints;
  const Rigid3d b_from_a = RandomMotion(rng);
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d p = PointInFront(rng);
    const Line3 line{p, p + 0.2 * RandomUnit(rng)};
    constraints.push_back(Constraint(b_from_a, line));
  }
  Eigen::Vector3d t;
  ASSERT_TRUE(TranslationFromStereoLines(b_from_a.rotation, kRightFromLeft, constraints.data(), 8, 1e-10, &t));
  EXPECT_LT((t - b_from_a.translation).norm(), 1e-12);
  // Negative control: a rotation 1 degree off moves t.
  const Eigen::Matrix3d off = ExpSO3(Eigen::Vector3d(0.0, M_PI / 180.0, 0.0)) * b_from_a.rotation;
  ASSERT_TRUE(TranslationFromStereoLines(off, kRightFromLeft, constraints.data(), 8, 1e-10, &t));
  EXPECT_GT((t - b_from_a.translation).norm(), 1e-3);
}

TEST(ThreeLineSolver, TranslationFromParallelLinesIsReported) {
  std::mt19937_64 rng(15);
  const Eigen::Vector3d d = RandomUnit(rng);
  const Rigid3d b_from_a = RandomMotion(rng);
  std::array<StereoLineConstraint, 4> constraints;
  for (StereoLineConstraint& c : constraints) {
    const Eigen::Vector3d p = PointInFront(rng);
    c = Constraint(b_from_a, Line3{p, p + 0.2 * d});
  }
  const Eigen::Vector3d unchanged(1.0, 2.0, 3.0);
  Eigen::Vector3d t = unchanged;
  // The rig is rectified, so every plane normal is orthogonal to d: t along d is free.
  EXPECT_FALSE(TranslationFromStereoLines(b_from_a.rotation, kRightFromLeft, constraints.data(), 4, 1e-10, &t));
  EXPECT_EQ(t, unchanged);
  EXPECT_FALSE(TranslationFromStereoLines(b_from_a.rotation, kRightFromLeft, constraints.data(), 0, 1e-10, &t));
}

}  // namespace
}  // namespace slt
