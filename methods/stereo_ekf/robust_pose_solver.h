// A per-frame robust pose solve: RANSAC over pairs of features (two features, 8 scalars,
// over-determine the 6-dof pose, paper Sec. 3.3; more when features measure fewer rows), each
// hypothesis refined by Gauss-Newton from the filter's prediction and scored with a truncated
// (MSAC) cost; the best is refined on its inliers. Used to seed the EKF when its prior is weak or when it has gone wrong.
#pragma once

#include <random>
#include <vector>

#include "methods/stereo_ekf/least_squares.h"

namespace slt {

struct RobustSolveResult {
  bool success = false;
  Rigid3d cam_from_ref;
  Matrix6d information = Matrix6d::Zero();  // J^T R^-1 J on the inliers at the solution
  std::vector<int> inliers;                  // feature indices
  int hypotheses = 0;
};

class RobustPoseSolver {
 public:
  void Reset(std::uint64_t seed) { rng_.seed(seed); }

  // `valid` lists the features with a usable block and whitener; `starts` are the poses every
  // hypothesis is refined from (e.g. the prediction and the previous pose), and are themselves
  // scored as hypotheses. `gate` gives the inlier threshold on the whitened squared residual.
  void Solve(const FeatureModel& model, const std::vector<WeightedFeature>& features,
             const std::vector<int>& valid, const std::vector<Rigid3d>& starts, const GateThresholds& gate,
             int max_iterations, double confidence, RobustSolveResult* result);

 private:
  static constexpr int kMaxSample = 6;  // features per hypothesis (6 rows of one each)

  // MSAC score of a pose; fills `inliers`.
  double Score(const FeatureModel& model, const std::vector<WeightedFeature>& features,
               const std::vector<int>& valid, const Rigid3d& pose, const GateThresholds& gate,
               std::vector<int>* inliers) const;

  std::mt19937_64 rng_{1};
  std::vector<int> scratch_inliers_;
};

}  // namespace slt
