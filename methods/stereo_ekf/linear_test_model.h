// A FeatureModel for the stereo EKF's tests (not linked into the trackers): feature i measures
//   r_i(M) = A_i (Log(M) - d_true) + (1 + growth |Log(M)|^2) offset_i,   covariance R_i,
// in the rows `rows_at_start` at M = I and `rows_away` elsewhere (a feature one of whose parts
// degenerates with the pose). The offset is a feature's noise or an outlier's error; a growth
// other than 0 makes the model not linear after all. On the first frame after the start
// (M_pred = I, where Log(Exp(d) M_pred) = d) the Jacobian A_i is exact.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "geometry/se3.h"
#include "methods/stereo_ekf/feature_model.h"
#include "methods/stereo_ekf/least_squares.h"

namespace slt {

class LinearTestModel final : public FeatureModel {
 public:
  struct Feature {
    Eigen::Matrix<double, 4, 6> a;
    Eigen::Matrix4d covariance = Eigen::Matrix4d::Identity();
    Eigen::Vector4d offset = Eigen::Vector4d::Zero();
    unsigned rows_at_start = FeatureBlock::kAllRows;
    unsigned rows_away = FeatureBlock::kAllRows;
  };

  // No feature yet (AddFeature).
  explicit LinearTestModel(const Vector6d& d_true) : d_true_(d_true) {}
  // `count` noise-free features, A_i standard normal draws from `seed`, R_i = variance * I.
  LinearTestModel(int count, std::uint64_t seed, double variance)
      : LinearTestModel((Vector6d() << 0.01, -0.02, 0.015, 0.02, 0.01, -0.01).finished()) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> normal;
    for (int i = 0; i < count; ++i) {
      Feature f;
      f.a = Eigen::Matrix<double, 4, 6>::NullaryExpr([&]() { return normal(rng); });
      f.covariance = variance * Eigen::Matrix4d::Identity();
      AddFeature(f);
    }
  }

  void AddFeature(const Feature& feature) { features_.push_back(feature); }
  const std::vector<Feature>& features() const { return features_; }
  Feature& feature(int index) { return features_[index]; }
  Rigid3d Truth() const { return ExpSE3(d_true_); }
  void set_offset_growth(double growth) { offset_growth_ = growth; }
  // Feature `index` can be measured at M = I only.
  void set_degenerate_away(int index) { degenerate_away_ = index; }

  void Reset(const StereoRig&) override {}
  int SetReference(const StereoFrame&) override { return NumFeatures(); }
  int SetCurrent(const StereoFrame&) override { return NumFeatures(); }
  int NumFeatures() const override { return static_cast<int>(features_.size()); }
  int CurrentStereoFeatures() const override { return NumFeatures(); }
  bool Evaluate(int index, const Rigid3d& cam_from_ref, bool with_covariance, FeatureBlock* block) const override {
    const Feature& f = features_[index];
    const Vector6d d = LogSE3(cam_from_ref);
    if (index == degenerate_away_ && d.norm() > 1e-12) return false;
    block->residual = f.a * (d - d_true_) + (1.0 + offset_growth_ * d.squaredNorm()) * f.offset;
    block->jacobian = f.a;
    if (with_covariance) block->covariance = f.covariance;
    block->measured_rows = d.norm() < 1e-12 ? f.rows_at_start : f.rows_away;
    block->ClearUnmeasuredRows(with_covariance);
    return true;
  }

 private:
  Vector6d d_true_;
  std::vector<Feature> features_;
  double offset_growth_ = 0.0;
  int degenerate_away_ = -1;
};

// Every feature of `model` evaluated at `at` with its covariance and whitened, as the filter
// does at its prediction. False if one cannot be.
inline bool WhitenedFeaturesAt(const FeatureModel& model, const Rigid3d& at, std::vector<WeightedFeature>* features) {
  features->assign(model.NumFeatures(), WeightedFeature());
  for (int i = 0; i < model.NumFeatures(); ++i) {
    if (!model.Evaluate(i, at, true, &(*features)[i].block) || !(*features)[i].FactorCovariance()) return false;
  }
  return true;
}

}  // namespace slt
