#include "common/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

namespace slt {
namespace {

TEST(ParallelFor, CallsEveryIndexOnceOnAnyNumberOfThreads) {
  for (int threads : {0, 1, 3, 64}) {
    std::vector<std::atomic<int>> calls(100);
    ParallelFor(calls.size(), threads, [&](size_t i) { ++calls[i]; });
    for (size_t i = 0; i < calls.size(); ++i) EXPECT_EQ(calls[i].load(), 1) << "index " << i << ", " << threads << " threads";
  }
  ParallelFor(0, 4, [](size_t) { FAIL() << "no index to run"; });
}

TEST(ParallelFor, TheFirstFailureStopsTheOthersAndIsRethrown) {
  std::atomic<int> ran{0};
  const auto fail_at_3 = [&](size_t i) {
    ++ran;
    if (i == 3) throw std::runtime_error("index 3 failed");
  };
  EXPECT_THROW(ParallelFor(1000, 1, fail_at_3), std::runtime_error);
  EXPECT_EQ(ran.load(), 4);  // one thread: nothing after the failing index
  // Several threads: the exception comes back to the caller (how many indices the others ran
  // before they saw the failure depends on the scheduling).
  try {
    ParallelFor(1000, 4, fail_at_3);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "index 3 failed");
  }
}

}  // namespace
}  // namespace slt
