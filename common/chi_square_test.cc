#include "common/chi_square.h"

#include <gtest/gtest.h>

namespace slt {
namespace {

TEST(ChiSquareQuantile, MatchesTabulatedValues) {
  // Reference values: scipy.stats.chi2.ppf(p, dof).
  EXPECT_NEAR(ChiSquareQuantile(0.999, 4), 18.466827, 1e-5);
  EXPECT_NEAR(ChiSquareQuantile(0.9999, 4), 23.512742, 1e-5);
  EXPECT_NEAR(ChiSquareQuantile(0.99, 4), 13.276704, 1e-5);
  EXPECT_NEAR(ChiSquareQuantile(0.5, 4), 3.356694, 1e-5);
  EXPECT_NEAR(ChiSquareQuantile(0.95, 6), 12.591587, 1e-5);
  EXPECT_NEAR(ChiSquareQuantile(0.999, 6), 22.457744, 1e-5);
  EXPECT_NEAR(ChiSquareQuantile(0.5, 1), 0.454936, 1e-5);
  EXPECT_NEAR(ChiSquareQuantile(0.99, 2), 9.210340, 1e-5);
}

TEST(ChiSquareQuantile, LowerTailAndManyDegreesOfFreedom) {
  // The ends of the 95 % NEES bands (evaluation/consistency.h); mpmath gammainc.
  EXPECT_NEAR(ChiSquareQuantile(0.025, 6), 1.237344, 1e-5);
  EXPECT_NEAR(ChiSquareQuantile(0.975, 6), 14.449375, 1e-5);
  EXPECT_NEAR(ChiSquareQuantile(0.025, 60), 40.481748, 1e-4);
  EXPECT_NEAR(ChiSquareQuantile(0.975, 60), 83.297672, 1e-4);
  EXPECT_NEAR(ChiSquareQuantile(0.025, 6000), 5787.1972, 1e-3);
}

}  // namespace
}  // namespace slt
