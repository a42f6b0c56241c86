#include "methods/stereo_ekf/robust_pose_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slt {

double RobustPoseSolver::Score(const FeatureModel& model, const std::vector<WeightedFeature>& features,
                               const std::vector<int>& valid, const Rigid3d& pose, const GateThresholds& gate,
                               std::vector<int>* inliers) const {
  inliers->clear();
  double score = 0.0;
  for (int i : valid) {
    double cost;
    const double g = gate(features[i].block);
    if (!WhitenedCost(model, features[i], i, pose, &cost) || cost >= g) {
      score += g;
      continue;
    }
    score += cost;
    inliers->push_back(i);
  }
  return score;
}

void RobustPoseSolver::Solve(const FeatureModel& model, const std::vector<WeightedFeature>& features,
                             const std::vector<int>& valid, const std::vector<Rigid3d>& starts,
                             const GateThresholds& gate, int max_iterations, double confidence, RobustSolveResult* result) {
  result->success = false;
  result->hypotheses = 0;
  result->inliers.clear();
  const int n = static_cast<int>(valid.size());
  if (n < 2) return;

  double best_score = std::numeric_limits<double>::infinity();
  Rigid3d best_pose;
  auto consider = [&](const Rigid3d& pose) {
    ++result->hypotheses;
    const double score = Score(model, features, valid, pose, gate, &scratch_inliers_);
    if (score < best_score) {
      best_score = score;
      best_pose = pose;
      result->inliers.swap(scratch_inliers_);
    }
  };
  for (const Rigid3d& start : starts) consider(start);

  std::uniform_int_distribution<int> pick(0, n - 1);
  int needed = max_iterations;
  int largest_sample = 2;
  Matrix6d information;
  for (int iteration = 0; iteration < needed && iteration < max_iterations; ++iteration) {
    // A minimal sample: distinct features until they measure the pose's 6 degrees of freedom --
    // two of 4 rows, three when lines are measured by one transfer only (2 rows each).
    int sample[kMaxSample];
    int count = 0, rows = 0;
    while (count < kMaxSample && count < n && (count < 2 || rows < 6)) {
      const int candidate = valid[pick(rng_)];
      if (std::find(sample, sample + count, candidate) != sample + count) continue;
      sample[count++] = candidate;
      rows += features[candidate].block.Dimension();
    }
    largest_sample = std::max(largest_sample, count);
    for (const Rigid3d& start : starts) {
      Rigid3d pose = start;
      if (RefinePose(model, features, sample, count, 6, &pose, &information)) consider(pose);
    }
    // Adaptive stopping: enough samples to draw an all-inlier sample with `confidence`.
    const double w = static_cast<double>(result->inliers.size()) / n;
    const double p_good = std::pow(w, largest_sample);
    if (p_good >= 1.0 - 1e-12) break;
    if (p_good > 0.0) {
      // Clamped in double: with many features and one inlier the count exceeds int.
      needed = static_cast<int>(std::min<double>(
          std::ceil(std::log(1.0 - confidence) / std::log(1.0 - p_good)), max_iterations));
    }
  }
  if (result->inliers.size() < 2) return;

  // Refine on the consensus set and re-collect the inliers at the refined pose; keep it if it
  // explains at least as many features, else the sample's pose and its inliers stand. Either way
  // the inliers are those inside the gate at the returned pose, and the information is theirs
  // there (the update that follows re-linearises and iterates from this start).
  Rigid3d pose = best_pose;
  if (RefinePose(model, features, result->inliers.data(), static_cast<int>(result->inliers.size()), 5, &pose,
                 &information)) {
    Score(model, features, valid, pose, gate, &scratch_inliers_);
    if (scratch_inliers_.size() >= result->inliers.size()) {
      result->inliers.swap(scratch_inliers_);
      best_pose = pose;
    }
  }
  // (The re-collected set replaces the consensus only when it is not smaller: still >= 2.)
  if (!RefinePose(model, features, result->inliers.data(), static_cast<int>(result->inliers.size()), 0,
                  &best_pose, &information)) {
    return;
  }
  result->cam_from_ref = best_pose;
  result->information = information;
  result->success = true;
}

}  // namespace slt
