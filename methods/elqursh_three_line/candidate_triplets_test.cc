#include "methods/elqursh_three_line/candidate_triplets.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "geometry/se3.h"

namespace slt {
namespace {

const PrimitiveConfigurationTolerances kTolerances{std::sin(3.0 * M_PI / 180.0), std::sin(3.0 * M_PI / 180.0)};

// Directions near three orthogonal axes (within 0-4 degrees, so some fail the 3-degree test),
// random ones, and unusable (zero) ones.
std::vector<Eigen::Vector3d> MixedDirections(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> tilt(0.0, 4.0 * M_PI / 180.0), any(-1.0, 1.0);
  const Eigen::Matrix3d axes = ExpSO3(Eigen::Vector3d(0.3, -0.5, 0.2));
  std::vector<Eigen::Vector3d> d;
  for (int i = 0; i < 24; ++i) {
    Eigen::Vector3d axis = axes.col(i % 3) * (i % 2 == 0 ? 1.0 : -1.0);
    const Eigen::Vector3d turn = Eigen::Vector3d(any(rng), any(rng), any(rng)).cross(axis).normalized() * tilt(rng);
    d.push_back(ExpSO3(turn) * axis);
  }
  for (int i = 0; i < 8; ++i) d.push_back(Eigen::Vector3d(any(rng), any(rng), any(rng)).normalized());
  d.push_back(Eigen::Vector3d::Zero());
  d.push_back(Eigen::Vector3d::Zero());
  return d;
}

// Every (i < j, k) by the definition in the header.
std::set<LineTriplet> BruteForce(const std::vector<Eigen::Vector3d>& d) {
  std::set<LineTriplet> out;
  const int n = static_cast<int>(d.size());
  const double s = kTolerances.max_parallel_sine, c = kTolerances.max_orthogonal_cosine;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (d[i].norm() == 0.0 || d[j].norm() == 0.0 || d[i].cross(d[j]).norm() > s) continue;
      for (int k = 0; k < n; ++k) {
        if (k == i || k == j || d[k].norm() == 0.0) continue;
        if (std::abs(d[k].dot(d[i])) <= c && std::abs(d[k].dot(d[j])) <= c) out.insert({i, j, k});
      }
    }
  }
  return out;
}

TEST(CandidateTriplets, ListsExactlyTheTripletsThatPassTheTest) {
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 10; ++trial) {
    const std::vector<Eigen::Vector3d> d = MixedDirections(rng);
    CandidateTriplets candidates;
    candidates.Build(d, kTolerances);
    std::set<LineTriplet> listed;
    for (std::int64_t n = 0; n < candidates.size(); ++n) listed.insert(candidates.At(n));
    EXPECT_EQ(listed.size(), static_cast<size_t>(candidates.size()));  // no triplet twice
    const std::set<LineTriplet> expected = BruteForce(d);
    EXPECT_EQ(listed, expected);
    EXPECT_GT(expected.size(), 100u);  // the test has something to find
  }
}

TEST(CandidateTriplets, ALongListIsSampledUniformly) {
  std::mt19937_64 rng(4);
  const std::vector<Eigen::Vector3d> d = MixedDirections(rng);
  CandidateTriplets candidates;
  candidates.Build(d, kTolerances);
  const std::set<LineTriplet> expected = BruteForce(d);
  std::map<LineTriplet, int> drawn;
  const int draws = 200 * static_cast<int>(expected.size());
  candidates.StartDraws(static_cast<int>(expected.size()) - 1);
  LineTriplet triplet;
  for (int i = 0; i < draws; ++i) {
    ASSERT_TRUE(candidates.Next(rng, &triplet));
    ++drawn[triplet];
  }
  ASSERT_EQ(drawn.size(), expected.size());
  for (const auto& [triplet, count] : drawn) {
    EXPECT_TRUE(expected.count(triplet));
    // Uniform: 200 expected per triplet, binomial standard deviation about 14.
    EXPECT_NEAR(count, 200, 80);
  }
}

TEST(CandidateTriplets, AShortListIsEnumeratedInARandomOrder) {
  std::mt19937_64 rng(6);
  const std::vector<Eigen::Vector3d> d = MixedDirections(rng);
  CandidateTriplets candidates;
  candidates.Build(d, kTolerances);
  std::vector<LineTriplet> first, second;
  for (std::vector<LineTriplet>* run : {&first, &second}) {
    candidates.StartDraws(static_cast<int>(candidates.size()));
    LineTriplet triplet;
    while (candidates.Next(rng, &triplet)) run->push_back(triplet);
    EXPECT_EQ(std::set<LineTriplet>(run->begin(), run->end()), BruteForce(d));  // each once
    EXPECT_EQ(run->size(), static_cast<size_t>(candidates.size()));
  }
  EXPECT_NE(first, second);
}

TEST(CandidateTriplets, RandomDirectionsRarelyFormOne) {
  // Independent random directions: a 3-degree pair has probability 1 - cos 3 deg = 0.0014.
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Eigen::Vector3d> d;
  for (int i = 0; i < 40; ++i) d.push_back(Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized());
  CandidateTriplets candidates;
  candidates.Build(d, kTolerances);
  EXPECT_EQ(candidates.size(), static_cast<std::int64_t>(BruteForce(d).size()));
  EXPECT_LE(candidates.parallel_pairs(), 5);
  // Nothing to find: an empty list.
  candidates.Build({Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()}, kTolerances);
  EXPECT_TRUE(candidates.empty());
  candidates.StartDraws(10);
  LineTriplet triplet;
  EXPECT_FALSE(candidates.Next(rng, &triplet));
  candidates.StartDraws(0);
  EXPECT_FALSE(candidates.Next(rng, &triplet));
}

TEST(CandidateTriplets, RolesInAnyOrder) {
  const std::vector<Eigen::Vector3d> d = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitX(),
                                          Eigen::Vector3d(1.0, 1.0, 0.0).normalized(), Eigen::Vector3d::Zero()};
  LineTriplet roles;
  for (const std::array<int, 3>& order : {std::array<int, 3>{0, 1, 2}, {1, 0, 2}, {2, 1, 0}, {0, 2, 1}}) {
    ASSERT_TRUE(AssignPrimitiveRoles(order, d, kTolerances, &roles));
    EXPECT_EQ(roles[2], 1);
    EXPECT_EQ(std::set<int>({roles[0], roles[1]}), std::set<int>({0, 2}));
  }
  EXPECT_FALSE(AssignPrimitiveRoles({0, 1, 3}, d, kTolerances, &roles));  // no parallel pair
  EXPECT_FALSE(AssignPrimitiveRoles({0, 2, 3}, d, kTolerances, &roles));  // 45 degrees: not orthogonal
  EXPECT_FALSE(AssignPrimitiveRoles({0, 2, 4}, d, kTolerances, &roles));  // unusable line
}

}  // namespace
}  // namespace slt
