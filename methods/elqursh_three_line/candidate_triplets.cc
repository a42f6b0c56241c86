#include "methods/elqursh_three_line/candidate_triplets.h"

#include <algorithm>

namespace slt {
namespace {

bool Usable(const Eigen::Vector3d& d) { return d.squaredNorm() > 0.5; }

// k is orthogonal to both lines of the pair (i, j), and is neither of them.
bool OrthogonalToPair(const std::vector<Eigen::Vector3d>& d, int i, int j, int k,
                      const PrimitiveConfigurationTolerances& t) {
  return k != i && k != j && Usable(d[k]) && t.Orthogonal(d[k], d[i]) && t.Orthogonal(d[k], d[j]);
}

}  // namespace

void CandidateTriplets::Build(const std::vector<Eigen::Vector3d>& d, const PrimitiveConfigurationTolerances& t) {
  pairs_.clear();
  offsets_.assign(1, 0);
  orthogonal_.clear();
  const int n = static_cast<int>(d.size());
  for (int i = 0; i < n; ++i) {
    if (!Usable(d[i])) continue;
    for (int j = i + 1; j < n; ++j) {
      if (!Usable(d[j]) || !t.Parallel(d[i], d[j])) continue;
      const size_t before = orthogonal_.size();
      for (int k = 0; k < n; ++k) {
        if (OrthogonalToPair(d, i, j, k, t)) orthogonal_.push_back(k);
      }
      if (orthogonal_.size() == before) continue;
      pairs_.emplace_back(i, j);
      offsets_.push_back(static_cast<std::int64_t>(orthogonal_.size()));
    }
  }
}

LineTriplet CandidateTriplets::At(std::int64_t n) const {
  // The pair p with offsets_[p] <= n < offsets_[p + 1].
  const auto p = std::upper_bound(offsets_.begin(), offsets_.end(), n) - offsets_.begin() - 1;
  return {pairs_[p].first, pairs_[p].second, orthogonal_[n]};
}

void CandidateTriplets::StartDraws(int max_draws) {
  enumerate_ = size() <= max_draws;
  drawn_ = 0;
  if (!enumerate_) return;
  order_.resize(orthogonal_.size());
  for (std::int64_t n = 0; n < size(); ++n) order_[n] = n;
}

bool CandidateTriplets::Next(std::mt19937_64& rng, LineTriplet* triplet) {
  if (empty()) return false;
  if (!enumerate_) {
    *triplet = At(std::uniform_int_distribution<std::int64_t>(0, size() - 1)(rng));
    return true;
  }
  if (drawn_ == size()) return false;
  const std::int64_t pick = std::uniform_int_distribution<std::int64_t>(drawn_, size() - 1)(rng);
  std::swap(order_[drawn_], order_[pick]);
  *triplet = At(order_[drawn_++]);
  return true;
}

bool AssignPrimitiveRoles(const std::array<int, 3>& lines, const std::vector<Eigen::Vector3d>& d,
                          const PrimitiveConfigurationTolerances& t, LineTriplet* roles) {
  for (int o = 2; o >= 0; --o) {
    const int i = lines[(o + 1) % 3], j = lines[(o + 2) % 3], k = lines[o];
    if (Usable(d[i]) && Usable(d[j]) && t.Parallel(d[i], d[j]) && OrthogonalToPair(d, i, j, k, t)) {
      *roles = {i, j, k};
      return true;
    }
  }
  return false;
}

}  // namespace slt
