#include "methods/stereo_ekf/least_squares.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <limits>
#include <random>

namespace slt {
namespace {

// A random symmetric positive-definite 6x6 matrix with condition number around 1e4, the range
// of a pose information matrix mixing radians and metres.
Matrix6d RandomSpd(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Matrix6d a;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) a(i, j) = normal(rng);
  Vector6d scale;
  scale << 1.0, 3.0, 10.0, 30.0, 60.0, 100.0;
  return scale.asDiagonal() * (a * a.transpose() + 0.1 * Matrix6d::Identity()) * scale.asDiagonal();
}

TEST(SpdSolver6, SolveInverseAndNormAgreeWithEigen) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 20; ++trial) {
    const Matrix6d a = RandomSpd(rng);
    Vector6d b;
    for (int i = 0; i < 6; ++i) b(i) = normal(rng);
    SpdSolver6 solver;
    ASSERT_TRUE(solver.Compute(a));
    const Eigen::LLT<Matrix6d> reference(a);
    const Vector6d x = solver.Solve(b);
    EXPECT_LT((x - reference.solve(b)).norm(), 1e-10 * (1.0 + x.norm()));
    EXPECT_LT((a * x - b).norm(), 1e-9 * (1.0 + b.norm()));
    EXPECT_LT((solver.Inverse() * a - Matrix6d::Identity()).norm(), 1e-9);
    // The lower factor reproduces a, and SquaredNorm is the quadratic form.
    const Matrix6d l = solver.lower();
    EXPECT_LT((l * l.transpose() - a).norm(), 1e-10 * a.norm());
    const double quadratic = b.dot(a * b);
    EXPECT_NEAR(solver.SquaredNorm(b), quadratic, 1e-12 * quadratic);
  }
}

TEST(SpdSolver6, RejectsMatricesThatAreNotPositiveDefinite) {
  Matrix6d a = Matrix6d::Identity();
  a(3, 3) = -1.0;
  SpdSolver6 solver;
  EXPECT_FALSE(solver.Compute(a));
  Matrix6d inverse;
  EXPECT_FALSE(InvertSpd6(a, &inverse));
  a(3, 3) = 0.0;  // singular
  EXPECT_FALSE(solver.Compute(a));
  a(3, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(solver.Compute(a));
}

TEST(InvertSpd6, InvertsPositiveDefiniteMatrices) {
  std::mt19937_64 rng(11);
  const Matrix6d a = RandomSpd(rng);
  Matrix6d inverse;
  ASSERT_TRUE(InvertSpd6(a, &inverse));
  EXPECT_LT((a * inverse - Matrix6d::Identity()).norm(), 1e-9);
}

}  // namespace
}  // namespace slt
