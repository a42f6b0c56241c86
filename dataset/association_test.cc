#include "dataset/association.h"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "dataset/stereo_sequence.h"

namespace slt {
namespace {

std::vector<LineObservation> WithIds(const std::vector<std::int64_t>& ids) {
  std::vector<LineObservation> out;
  for (std::int64_t id : ids) {
    LineObservation o;
    o.id = id;
    o.segment << static_cast<double>(id), 0.0, 0.0, 0.0;
    out.push_back(o);
  }
  return out;
}

std::vector<std::pair<size_t, size_t>> Join(const std::vector<LineObservation>& a,
                                            const std::vector<LineObservation>& b) {
  std::vector<std::pair<size_t, size_t>> matches;
  JoinById(a, b, [&](size_t i, size_t j) { matches.emplace_back(i, j); });
  return matches;
}

TEST(JoinById, PairsEqualIdsOnly) {
  const auto a = WithIds({1, 3, 4, 7, 9});
  const auto b = WithIds({0, 3, 5, 7, 9, 12});
  const std::vector<std::pair<size_t, size_t>> expected = {{1, 1}, {3, 3}, {4, 4}};
  EXPECT_EQ(Join(a, b), expected);
  EXPECT_TRUE(Join(a, WithIds({})).empty());
  EXPECT_TRUE(Join(WithIds({2, 4}), WithIds({1, 3, 5})).empty());
}

TEST(JoinById, DuplicatedIdsPairInOrder) {
  // Two 5s on the left, three on the right: the first two of each pair up, the third is left out.
  const auto a = WithIds({5, 5, 6});
  const auto b = WithIds({5, 5, 5, 6});
  const std::vector<std::pair<size_t, size_t>> expected = {{0, 0}, {1, 1}, {2, 3}};
  EXPECT_EQ(Join(a, b), expected);
}

TEST(ContainsId, FindsExactlyTheIdsOfASortedRange) {
  const auto sorted = WithIds({1, 3, 4, 7, 9});
  for (std::int64_t id : {1, 3, 4, 7, 9}) EXPECT_TRUE(ContainsId(sorted, id)) << id;
  for (std::int64_t id : {-1, 0, 2, 5, 8, 10}) EXPECT_FALSE(ContainsId(sorted, id)) << id;
  EXPECT_FALSE(ContainsId(WithIds({}), std::int64_t{1}));
}

TEST(SortedById, ReturnsTheInputWhenSortedAndASortedCopyOtherwise) {
  std::vector<LineObservation> scratch;
  const auto sorted = WithIds({1, 2, 8});
  EXPECT_EQ(&SortedById(sorted, &scratch), &sorted);
  EXPECT_TRUE(scratch.empty());
  const auto unsorted = WithIds({8, 1, 2});
  const std::vector<LineObservation>& result = SortedById(unsorted, &scratch);
  EXPECT_EQ(&result, &scratch);
  ASSERT_EQ(result.size(), 3u);
  EXPECT_EQ(result[0].id, 1);
  EXPECT_EQ(result[2].id, 8);
  EXPECT_EQ(result[2].segment(0), 8.0);  // the elements move with their ids
}

}  // namespace
}  // namespace slt
