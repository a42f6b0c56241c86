#include "common/random.h"

#include <gtest/gtest.h>

namespace slt {
namespace {

TEST(Random, StreamsAreReproducibleAndIndependent) {
  RandomStream a = MakeStream(42, "noise"), b = MakeStream(42, "noise");
  RandomStream c = MakeStream(42, "scene"), d = MakeStream(43, "noise");
  const auto first = a();
  EXPECT_EQ(first, b());
  EXPECT_NE(first, c());
  EXPECT_NE(first, d());
  EXPECT_NE(TrialSeed(1, 0), TrialSeed(1, 1));
  EXPECT_EQ(TrialSeed(1, 5), TrialSeed(1, 5));
}

}  // namespace
}  // namespace slt
