// A FeatureModel for the stereo EKF's unit tests (not linked into the trackers): feature i
// measures
//   r_i(M) = A_i (Log(M) - d_true) + offset_i,   covariance variance * I,
// noise-free, in the rows `rows_at_start` at M = I and `rows_away` elsewhere (a feature one of
// whose parts degenerates with the pose). The A_i are standard normal draws from `seed`.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "geometry/se3.h"
#include "methods/stereo_ekf/feature_model.h"

namespace slt {

class LinearTestModel final : public FeatureModel {
 public:
  struct Feature {
    Eigen::Matrix<double, 4, 6> a;
    Eigen::Vector4d offset = Eigen::Vector4d::Zero();
    unsigned rows_at_start = FeatureBlock::kAllRows;
    unsigned rows_away = FeatureBlock::kAllRows;
  };

  LinearTestModel(int count, std::uint64_t seed, double variance) : features_(count), variance_(variance) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> normal;
    for (Feature& f : features_) f.a = Eigen::Matrix<double, 4, 6>::NullaryExpr([&]() { return normal(rng); });
    d_true_ << 0.01, -0.02, 0.015, 0.02, 0.01, -0.01;
  }

  Feature& feature(int index) { return features_[index]; }
  Rigid3d Truth() const { return ExpSE3(d_true_); }

  void Reset(const StereoRig&) override {}
  int SetReference(const StereoFrame&) override { return NumFeatures(); }
  int SetCurrent(const StereoFrame&) override { return NumFeatures(); }
  int NumFeatures() const override { return static_cast<int>(features_.size()); }
  int CurrentStereoFeatures() const override { return NumFeatures(); }
  bool Evaluate(int index, const Rigid3d& cam_from_ref, bool with_covariance, FeatureBlock* block) const override {
    const Feature& f = features_[index];
    const Vector6d d = LogSE3(cam_from_ref);
    block->residual = f.a * (d - d_true_) + f.offset;
    block->jacobian = f.a;
    if (with_covariance) block->covariance = variance_ * Eigen::Matrix4d::Identity();
    block->measured_rows = d.norm() < 1e-12 ? f.rows_at_start : f.rows_away;
    block->ClearUnmeasuredRows(with_covariance);
    return true;
  }

 private:
  std::vector<Feature> features_;
  double variance_;
  Vector6d d_true_;
};

}  // namespace slt
