#include "optim/ransac.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <random>
#include <vector>

namespace slt {
namespace {

// A 2-D line a x + b y + c = 0 with (a, b) of unit length: the line through two points, the
// squared point-line distance as cost, the total-least-squares line of the inliers as local
// optimisation.
struct Line2 {
  Eigen::Vector3d abc = Eigen::Vector3d::Zero();
};

class LineFitEstimator : public FixedSampleSize<2> {
 public:
  using Model = Line2;
  LineFitEstimator(const std::vector<Eigen::Vector2d>& points, double threshold)
      : points_(points), threshold_(threshold) {}

  int NumData() const { return static_cast<int>(points_.size()); }
  void MinimalSolve(const int* sample, int count, std::vector<Model>* models) const {
    ASSERT_EQ(count, 2);
    const Eigen::Vector3d p(points_[sample[0]].x(), points_[sample[0]].y(), 1.0);
    const Eigen::Vector3d q(points_[sample[1]].x(), points_[sample[1]].y(), 1.0);
    const Eigen::Vector3d l = p.cross(q);
    const double norm = l.head<2>().norm();
    if (!(norm > 0.0)) return;
    models->push_back({l / norm});
  }
  bool Cost(int datum, const Model& model, double* cost) const {
    const double d = model.abc.head<2>().dot(points_[datum]) + model.abc(2);
    *cost = d * d;
    return true;
  }
  double Threshold(int) const { return threshold_ * threshold_; }
  bool LocalOptimize(const std::vector<int>& inliers, Model* model) const {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (int i : inliers) mean += points_[i];
    mean /= inliers.size();
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (int i : inliers) scatter += (points_[i] - mean) * (points_[i] - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(scatter);
    const Eigen::Vector2d normal = eigen.eigenvectors().col(0);  // smallest eigenvalue
    model->abc << normal, -normal.dot(mean);
    return true;
  }

 private:
  const std::vector<Eigen::Vector2d>& points_;
  double threshold_;
};

// Points on y = 0.5 x + 1 (noise-free), then `outliers` points uniform in [-10, 10]^2 far off it.
std::vector<Eigen::Vector2d> LinePoints(int inliers, int outliers, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < inliers; ++i) {
    const double x = u(rng);
    points.emplace_back(x, 0.5 * x + 1.0);
  }
  while (static_cast<int>(points.size()) < inliers + outliers) {
    const Eigen::Vector2d p(u(rng), u(rng));
    if (std::abs(0.5 * p.x() - p.y() + 1.0) / std::sqrt(1.25) > 1.0) points.push_back(p);
  }
  return points;
}

// Distance of the fitted line to y = 0.5 x + 1 as the angle between normals and the offset.
double LineError(const Line2& line) {
  Eigen::Vector3d truth(0.5, -1.0, 1.0);
  truth /= truth.head<2>().norm();
  const double sign = truth.dot(line.abc) < 0.0 ? -1.0 : 1.0;
  return (sign * line.abc - truth).norm();
}

TEST(Ransac, ExactOnNoiseFreeInliers) {
  const std::vector<Eigen::Vector2d> points = LinePoints(30, 10, 1);
  Ransac<Line2> ransac(7);
  RansacResult<Line2> result;
  ransac.Run(LineFitEstimator(points, 0.1), RansacOptions(), {}, &result);
  ASSERT_TRUE(result.success);
  EXPECT_LT(LineError(result.model), 1e-12);
  EXPECT_EQ(result.inliers.size(), 30u);
}

TEST(Ransac, FindsTheLineAtHalfOutliers) {
  const std::vector<Eigen::Vector2d> points = LinePoints(40, 40, 2);
  Ransac<Line2> ransac(3);
  RansacResult<Line2> result;
  ransac.Run(LineFitEstimator(points, 0.1), RansacOptions(), {}, &result);
  ASSERT_TRUE(result.success);
  std::vector<int> expected(40);
  for (int i = 0; i < 40; ++i) expected[i] = i;
  EXPECT_EQ(result.inliers, expected);
  EXPECT_LT(LineError(result.model), 1e-12);
  // At w = 1/2 and 99.9 %: about log(0.001) / log(0.75) = 24 samples, not the 200 allowed.
  EXPECT_LT(result.samples, 200);
}

TEST(Ransac, DeterministicForASeed) {
  const std::vector<Eigen::Vector2d> points = LinePoints(20, 30, 4);
  RansacOptions options;
  options.max_iterations = 15;  // few samples: different seeds end at different models
  auto run = [&](std::uint64_t seed) {
    Ransac<Line2> ransac(seed);
    RansacResult<Line2> result;
    ransac.Run(LineFitEstimator(points, 0.1), options, {}, &result);
    return result;
  };
  const RansacResult<Line2> a = run(11), b = run(11);
  EXPECT_EQ(a.inliers, b.inliers);
  EXPECT_EQ(a.samples, b.samples);
  EXPECT_EQ(a.model.abc, b.model.abc);  // bitwise
  // Reset restarts the stream: the second run of one object equals the first.
  Ransac<Line2> ransac(11);
  RansacResult<Line2> first, second;
  ransac.Run(LineFitEstimator(points, 0.1), options, {}, &first);
  ransac.Reset(11);
  ransac.Run(LineFitEstimator(points, 0.1), options, {}, &second);
  EXPECT_EQ(first.model.abc, second.model.abc);
}

TEST(Ransac, StopsAfterOneSampleWhenEveryDatumIsAnInlier) {
  const std::vector<Eigen::Vector2d> points = LinePoints(50, 0, 5);
  Ransac<Line2> ransac(1);
  RansacResult<Line2> result;
  ransac.Run(LineFitEstimator(points, 0.1), RansacOptions(), {}, &result);
  ASSERT_TRUE(result.success);
  EXPECT_EQ(result.samples, 1);
  EXPECT_EQ(result.hypotheses, 1);
}

TEST(Ransac, FailsOnTooFewData) {
  const std::vector<Eigen::Vector2d> one = {{1.0, 1.5}};
  Ransac<Line2> ransac(1);
  RansacResult<Line2> result;
  ransac.Run(LineFitEstimator(one, 0.1), RansacOptions(), {Line2()}, &result);
  EXPECT_FALSE(result.success);
  EXPECT_EQ(result.hypotheses, 0);
  EXPECT_TRUE(result.inliers.empty());
}

TEST(Ransac, ScoresTheCallersHypothesesFirst) {
  // The true line given as an extra hypothesis explains every inlier; with one sample allowed
  // (and outliers everywhere) sampling alone would rarely find it.
  const std::vector<Eigen::Vector2d> points = LinePoints(10, 40, 6);
  Line2 truth;
  truth.abc << 0.5, -1.0, 1.0;
  truth.abc /= truth.abc.head<2>().norm();
  RansacOptions options;
  options.max_iterations = 1;
  Ransac<Line2> ransac(1);
  RansacResult<Line2> result;
  ransac.Run(LineFitEstimator(points, 0.1), options, {truth}, &result);
  ASSERT_TRUE(result.success);
  EXPECT_EQ(result.inliers.size(), 10u);
  EXPECT_EQ(result.hypotheses, 2);  // the given line and the one sample's
}

// A minimal solver returning several hypotheses per sample (as a closed-form solver with up to
// four rotations does): the line through the sample and a wrong one. The loop must score both
// and keep the right one; without LocalOptimize the model is the sampled line itself.
class TwoHypothesisEstimator : public FixedSampleSize<2> {
 public:
  using Model = Line2;
  explicit TwoHypothesisEstimator(const std::vector<Eigen::Vector2d>& points) : line_(points, 0.1) {}
  int NumData() const { return line_.NumData(); }
  void MinimalSolve(const int* sample, int count, std::vector<Model>* models) const {
    models->push_back({Eigen::Vector3d(1.0, 0.0, 100.0)});  // x = -100: explains nothing
    line_.MinimalSolve(sample, count, models);
  }
  bool Cost(int datum, const Model& model, double* cost) const { return line_.Cost(datum, model, cost); }
  double Threshold(int datum) const { return line_.Threshold(datum); }

 private:
  LineFitEstimator line_;
};

TEST(Ransac, ScoresEveryHypothesisOfASample) {
  const std::vector<Eigen::Vector2d> points = LinePoints(30, 0, 8);
  Ransac<Line2> ransac(2);
  RansacResult<Line2> result;
  ransac.Run(TwoHypothesisEstimator(points), RansacOptions(), {}, &result);
  ASSERT_TRUE(result.success);
  EXPECT_EQ(result.hypotheses, 2);
  EXPECT_EQ(result.inliers.size(), 30u);
  EXPECT_LT(LineError(result.model), 1e-9);
}

// Variable sample size: data carry a weight and a sample is complete once its weights reach 3
// (as features measuring 2 or 4 rows complete a 6-row pose sample); at most 4 data.
class WeightedSampleEstimator {
 public:
  using Model = Line2;
  WeightedSampleEstimator(const std::vector<Eigen::Vector2d>& points, const std::vector<int>& weights,
                          std::vector<int>* sizes)
      : line_(points, 0.1), weights_(weights), sizes_(sizes) {}
  int NumData() const { return line_.NumData(); }
  int MinSampleSize() const { return 2; }
  int MaxSampleSize() const { return 4; }
  bool SampleComplete(const int* sample, int count) const {
    int weight = 0;
    for (int k = 0; k < count; ++k) weight += weights_[sample[k]];
    return weight >= 3;
  }
  void MinimalSolve(const int* sample, int count, std::vector<Model>* models) const {
    sizes_->push_back(count);
    line_.MinimalSolve(sample, 2, models);
  }
  bool Cost(int datum, const Model& model, double* cost) const { return line_.Cost(datum, model, cost); }
  double Threshold(int datum) const { return line_.Threshold(datum); }

 private:
  LineFitEstimator line_;
  const std::vector<int>& weights_;
  std::vector<int>* sizes_;
};

TEST(Ransac, DrawsUntilTheEstimatorCallsTheSampleComplete) {
  const std::vector<Eigen::Vector2d> points = LinePoints(6, 6, 9);
  // Weight 1 everywhere: 3 data complete a sample; weight 2 on the first half: 2 do when one
  // of them is in it.
  std::vector<int> ones(points.size(), 1), mixed(points.size(), 1);
  for (size_t i = 0; i < points.size() / 2; ++i) mixed[i] = 2;
  RansacOptions options;
  options.max_iterations = 30;
  std::vector<int> sizes;
  Ransac<Line2> ransac(4);
  RansacResult<Line2> result;
  ransac.Run(WeightedSampleEstimator(points, ones, &sizes), options, {}, &result);
  ASSERT_FALSE(sizes.empty());
  for (int size : sizes) EXPECT_EQ(size, 3);
  sizes.clear();
  ransac.Run(WeightedSampleEstimator(points, mixed, &sizes), options, {}, &result);
  bool saw_two = false, saw_three = false;
  for (int size : sizes) {
    EXPECT_TRUE(size == 2 || size == 3) << size;
    saw_two |= size == 2;
    saw_three |= size == 3;
  }
  EXPECT_TRUE(saw_two && saw_three);
}

// Samples drawn by the estimator: only pairs of the first `usable` points (the others are
// outliers the estimator knows not to sample), and no more than `budget` of them.
class OwnSamplerEstimator {
 public:
  using Model = Line2;
  OwnSamplerEstimator(const std::vector<Eigen::Vector2d>& points, int usable, int budget, std::vector<int>* drawn)
      : line_(points, 0.1), usable_(usable), budget_(budget), drawn_(drawn) {}
  int NumData() const { return line_.NumData(); }
  int MinSampleSize() const { return 2; }
  int MaxSampleSize() const { return 2; }
  bool SampleComplete(const int*, int) const { return true; }
  int DrawSample(std::mt19937_64& rng, int* sample) const {
    if (static_cast<int>(drawn_->size()) == 2 * budget_) return 0;
    std::uniform_int_distribution<int> pick(0, usable_ - 1);
    sample[0] = pick(rng);
    do sample[1] = pick(rng);
    while (sample[1] == sample[0]);
    drawn_->insert(drawn_->end(), sample, sample + 2);
    return 2;
  }
  void MinimalSolve(const int* sample, int count, std::vector<Model>* models) const {
    line_.MinimalSolve(sample, count, models);
  }
  bool Cost(int datum, const Model& model, double* cost) const { return line_.Cost(datum, model, cost); }
  double Threshold(int datum) const { return line_.Threshold(datum); }

 private:
  LineFitEstimator line_;
  int usable_;
  int budget_;
  std::vector<int>* drawn_;
};

TEST(Ransac, AnEstimatorMayDrawItsOwnSamples) {
  // 5 inliers among 45 outliers: uniform pairs are all-inlier with probability 0.8 %, the
  // estimator's pairs always.
  std::vector<Eigen::Vector2d> points = LinePoints(5, 45, 10);
  std::vector<int> drawn;
  Ransac<Line2> ransac(5);
  RansacResult<Line2> result;
  RansacOptions options;
  options.max_iterations = 3;
  ransac.Run(OwnSamplerEstimator(points, 5, 100, &drawn), options, {}, &result);
  ASSERT_TRUE(result.success);
  EXPECT_EQ(result.inliers.size(), 5u);
  for (int d : drawn) EXPECT_LT(d, 5);
  EXPECT_EQ(result.samples, static_cast<int>(drawn.size()) / 2);
  // Same seed, same draws.
  std::vector<int> again;
  ransac.Reset(5);
  ransac.Run(OwnSamplerEstimator(points, 5, 100, &again), options, {}, &result);
  EXPECT_EQ(again, drawn);
  // An estimator out of samples stops the loop: one sample here, though 3 are allowed.
  drawn.clear();
  ransac.Run(OwnSamplerEstimator(points, 5, 1, &drawn), options, {}, &result);
  EXPECT_EQ(result.samples, 1);
  EXPECT_EQ(drawn.size(), 2u);
  drawn.clear();
  ransac.Run(OwnSamplerEstimator(points, 5, 0, &drawn), options, {}, &result);
  EXPECT_EQ(result.samples, 0);
  EXPECT_FALSE(result.success);
}

}  // namespace
}  // namespace slt
