#include "methods/stereo_ekf/robust_pose_solver.h"

namespace slt {

bool PoseFromFeatures::SampleComplete(const int* sample, int count) const {
  int rows = 0;
  for (int k = 0; k < count; ++k) rows += features_[valid_[sample[k]]].block.Dimension();
  return rows >= 6;
}

void PoseFromFeatures::MinimalSolve(const int* sample, int count, std::vector<Rigid3d>* models) const {
  int indices[kMaxSample];
  for (int k = 0; k < count; ++k) indices[k] = valid_[sample[k]];
  Matrix6d information;
  for (const Rigid3d& start : starts_) {
    Rigid3d pose = start;
    if (RefinePose(model_, features_, indices, count, 6, &pose, &information, max_sigma_)) models->push_back(pose);
  }
}

bool PoseFromFeatures::LocalOptimize(const std::vector<int>& inliers, Rigid3d* cam_from_ref) const {
  indices_.clear();
  for (int d : inliers) indices_.push_back(valid_[d]);
  Matrix6d information;
  return RefinePose(model_, features_, indices_.data(), static_cast<int>(indices_.size()), 5, cam_from_ref,
                    &information, max_sigma_);
}

void RobustPoseSolver::Solve(const FeatureModel& model, const std::vector<WeightedFeature>& features,
                             const std::vector<int>& valid, const std::vector<Rigid3d>& starts,
                             const GateThresholds& gate, const RansacOptions& options, double max_sigma,
                             RobustSolveResult* result) {
  result->success = false;
  result->inliers.clear();
  ransac_.Run(PoseFromFeatures(model, features, valid, starts, gate, max_sigma), options, starts, &ransac_result_);
  if (!ransac_result_.success) return;
  for (int d : ransac_result_.inliers) result->inliers.push_back(valid[d]);
  result->cam_from_ref = ransac_result_.model;
  if (!RefinePose(model, features, result->inliers.data(), static_cast<int>(result->inliers.size()), 0,
                  &result->cam_from_ref, &result->information)) {
    result->success = false;
    return;
  }
  result->success = true;
}

}  // namespace slt
