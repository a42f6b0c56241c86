// The iterated update of the shared stereo EKF (methods/stereo_ekf) does what its options say:
// one Gauss-Newton step for the paper's EKF, up to max_iterations re-linearisations otherwise,
// stopping once a step is shorter than iteration_tolerance posterior standard deviations.
#include <gtest/gtest.h>

#include "methods/stereo_ekf/stereo_ekf_tracker.h"
#include "tests/test_support.h"

namespace slt {
namespace {

StereoEkfTracker::Counters RunAndCount(const std::string& method, const nlohmann::json& filter,
                                       const SimulatedSequence& sim) {
  auto tracker = CreateTracker(method, {{"filter", filter}});
  auto* ekf = dynamic_cast<StereoEkfTracker*>(tracker.get());
  EXPECT_NE(ekf, nullptr) << method << " is not a stereo EKF tracker";
  if (ekf == nullptr) return {};
  RunTracker(*tracker, sim.sequence);
  return ekf->counters();
}

class IteratedUpdate : public ::testing::TestWithParam<std::string> {};

TEST_P(IteratedUpdate, IteratesAsConfigured) {
  const SimulatedSequence sim =
      Simulate(SimulationConfigFromJson({{"frames", 30}, {"noise", {{"endpoint_px", 1.0}}}}, "test"));

  const auto single = RunAndCount(GetParam(), {{"max_iterations", 1}}, sim);
  ASSERT_GT(single.updates, 20);
  EXPECT_EQ(single.update_iterations, single.updates);

  // Tolerance 0: every update runs all its iterations.
  const auto all = RunAndCount(GetParam(), {{"max_iterations", 4}, {"iteration_tolerance", 0.0}}, sim);
  ASSERT_GT(all.updates, 20);
  EXPECT_EQ(all.update_iterations, 4 * all.updates);

  // The default tolerance (0.1 posterior sigma): the second step of an update from a good
  // prediction is already negligible, so most updates stop after two iterations, not four.
  const auto early = RunAndCount(GetParam(), {{"max_iterations", 4}}, sim);
  EXPECT_GT(early.update_iterations, early.updates);
  EXPECT_LT(early.update_iterations, 3 * early.updates);
}

INSTANTIATE_TEST_SUITE_P(StereoEkfTrackers, IteratedUpdate,
                         ::testing::Values("trifocal_line_ekf", "yu_point_ekf"));

}  // namespace
}  // namespace slt
