// A per-frame robust pose solve: the project's RANSAC (optim/ransac.h) with one estimator,
// PoseFromFeatures. A minimal sample is two features (8 scalars over-determine the 6-dof pose,
// paper Sec. 3.3), more when features measure fewer rows; each sample gives one hypothesis per
// start pose, refined by Gauss-Newton from it; hypotheses are scored with the truncated (MSAC)
// whitened cost against the validation gate; the best is refined on its inliers. Used to seed
// the EKF when its prior is weak or when it has gone wrong.
#pragma once

#include <random>
#include <vector>

#include "methods/stereo_ekf/least_squares.h"
#include "optim/ransac.h"

namespace slt {

// The RANSAC estimator of a pose from features (datum d = feature valid[d]).
class PoseFromFeatures {
 public:
  using Model = Rigid3d;
  static constexpr int kMaxSample = 6;  // features per sample (6 rows of one each)

  // `valid` lists the features with a usable block and whitener; `starts` are the poses every
  // sample's hypothesis is refined from (one hypothesis per start). `gate` gives the inlier
  // threshold on the whitened squared residual; max_sigma, the directions a hypothesis and the
  // consensus refinement solve (RefinePose).
  PoseFromFeatures(const FeatureModel& model, const std::vector<WeightedFeature>& features,
                   const std::vector<int>& valid, const std::vector<Rigid3d>& starts, const GateThresholds& gate,
                   double max_sigma)
      : model_(model), features_(features), valid_(valid), starts_(starts), gate_(gate), max_sigma_(max_sigma) {}

  int NumData() const { return static_cast<int>(valid_.size()); }
  int MinSampleSize() const { return 2; }
  int MaxSampleSize() const { return kMaxSample; }
  // Complete once the sample measures the pose's 6 degrees of freedom: two features of 4 rows,
  // three when lines are measured by one transfer only (2 rows each).
  bool SampleComplete(const int* sample, int count) const;
  void MinimalSolve(const int* sample, int count, std::vector<Rigid3d>* models) const;
  bool Cost(int datum, const Rigid3d& cam_from_ref, double* cost) const {
    const int i = valid_[datum];
    return WhitenedCost(model_, features_[i], i, cam_from_ref, cost);
  }
  double Threshold(int datum) const { return gate_(features_[valid_[datum]].block); }
  // Five Gauss-Newton iterations on the consensus.
  bool LocalOptimize(const std::vector<int>& inliers, Rigid3d* cam_from_ref) const;

 private:
  const FeatureModel& model_;
  const std::vector<WeightedFeature>& features_;
  const std::vector<int>& valid_;
  const std::vector<Rigid3d>& starts_;
  const GateThresholds& gate_;
  const double max_sigma_;
  mutable std::vector<int> indices_;  // feature indices of a datum set
};

struct RobustSolveResult {
  bool success = false;
  Rigid3d cam_from_ref;
  Matrix6d information = Matrix6d::Zero();  // J^T R^-1 J on the inliers at the solution
  std::vector<int> inliers;                  // feature indices
};

class RobustPoseSolver {
 public:
  void Reset(std::uint64_t seed) { ransac_.Reset(seed); }

  // Runs RANSAC with PoseFromFeatures; the starts are also scored as hypotheses themselves.
  // On success the inliers are those inside the gate at the returned pose, and the information
  // is theirs there (the update that follows re-linearises and iterates from this start).
  void Solve(const FeatureModel& model, const std::vector<WeightedFeature>& features,
             const std::vector<int>& valid, const std::vector<Rigid3d>& starts, const GateThresholds& gate,
             const RansacOptions& options, double max_sigma, RobustSolveResult* result);

 private:
  Ransac<Rigid3d> ransac_;
  RansacResult<Rigid3d> ransac_result_;
};

}  // namespace slt
