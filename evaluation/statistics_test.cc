#include "evaluation/statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace slt {
namespace {

TEST(Statistics, QuantileInterpolatesLinearlyBetweenOrderStatistics) {
  // Values checked against numpy.percentile (default "linear" method).
  EXPECT_DOUBLE_EQ(Quantile({4, 1, 3, 2}, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(Quantile({4, 1, 3, 2}, 0.025), 1.075);
  EXPECT_DOUBLE_EQ(Quantile({4, 1, 3, 2}, 0.975), 3.925);
  EXPECT_DOUBLE_EQ(Quantile({4, 1, 3, 2}, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(Quantile({4, 1, 3, 2}, 1.0), 4.0);
  std::vector<double> twenty;
  for (int i = 0; i < 20; ++i) twenty.push_back(i);
  EXPECT_DOUBLE_EQ(Quantile(twenty, 0.025), 0.475);  // np.percentile(range(20), 2.5)
  EXPECT_DOUBLE_EQ(Quantile(twenty, 0.975), 18.525);
  EXPECT_DOUBLE_EQ(Quantile({7}, 0.975), 7.0);
  EXPECT_TRUE(std::isnan(Quantile({}, 0.5)));
}

TEST(Statistics, SummaryLeavesOutNonFiniteValues) {
  const Summary s = Summarize({1, 2, std::nan(""), 3, 10});
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(s.mean, 4.0);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.p2_5, 1.075);
  EXPECT_DOUBLE_EQ(s.p97_5, 10 - 0.075 * 7);
  const Summary none = Summarize({std::nan("")});
  EXPECT_EQ(none.count, 0u);
  EXPECT_TRUE(std::isnan(none.mean));
}

}  // namespace
}  // namespace slt
