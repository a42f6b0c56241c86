#include "common/chi_square.h"

#include <gtest/gtest.h>

namespace slt {
namespace {

TEST(ChiSquareQuantile, MatchesTabulatedValues) {
  // Reference values: scipy.stats.chi2.ppf(p, dof); the lower tail and the many degrees of
  // freedom (ends of the 95 % NEES bands, evaluation/consistency.h) from mpmath's gammainc.
  struct Case {
    double p;
    int dof;
    double expected, tolerance;
  };
  for (const Case& c : {Case{0.999, 4, 18.466827, 1e-5}, Case{0.9999, 4, 23.512742, 1e-5},
                        Case{0.99, 4, 13.276704, 1e-5}, Case{0.5, 4, 3.356694, 1e-5}, Case{0.95, 6, 12.591587, 1e-5},
                        Case{0.999, 6, 22.457744, 1e-5}, Case{0.5, 1, 0.454936, 1e-5}, Case{0.99, 2, 9.210340, 1e-5},
                        Case{0.025, 6, 1.237344, 1e-5}, Case{0.975, 6, 14.449375, 1e-5},
                        Case{0.025, 60, 40.481748, 1e-4}, Case{0.975, 60, 83.297675, 1e-4},
                        Case{0.025, 6000, 5787.1972, 1e-3}}) {
    EXPECT_NEAR(ChiSquareQuantile(c.p, c.dof), c.expected, c.tolerance) << "p " << c.p << ", dof " << c.dof;
  }
}

}  // namespace
}  // namespace slt
