// The measurement side of the stereo EKF trackers: one model per feature type (lines in
// trifocal_line_ekf, points in yu_point_ekf), one shared filter (stereo_ekf_tracker.h).
//
// A model matches the features of a reference stereo pair (I_1, I'_1) with those of the
// current pair (I_t, I'_t) and, for a pose cam_from_ref = M_t of the current left camera,
// returns for each matched feature four residual scalars r(M_t) (or fewer, see
// FeatureBlock::measured_rows) that vanish for noise-free data at the true pose, their Jacobian
// with respect to a pose perturbation M_t <- Exp(d) M_t (docs/conventions.md), and, when asked,
// their covariance under the measurement noise.
#pragma once

#include <Eigen/Core>
#include <bitset>
#include <cstdint>
#include <vector>
#include <nlohmann/json.hpp>

#include "common/options.h"
#include "dataset/stereo_sequence.h"
#include "geometry/rigid3.h"
#include "geometry/se3.h"

namespace slt {

struct FeatureBlock {
  Eigen::Vector4d residual;
  Eigen::Matrix<double, 4, 6> jacobian;  // d residual / d delta
  Eigen::Matrix4d covariance;            // filled only when asked for
  // The residual rows that carry a measurement (bit i: row i). A model leaves rows out when the
  // part of the feature they measure is degenerate at this pose while the rest is not (one of a
  // line's two transfers, paper Sec. 4). ClearUnmeasuredRows gives those rows a zero residual
  // and Jacobian and the covariance rows and columns of the identity: whitening then gives them
  // no weight, and the gate compares with the quantile of Dimension() degrees of freedom.
  static constexpr unsigned kAllRows = 0xF;
  unsigned measured_rows = kAllRows;

  int Dimension() const { return static_cast<int>(std::bitset<4>(measured_rows).count()); }
  void ClearUnmeasuredRows(bool with_covariance) {
    if (measured_rows == kAllRows) return;
    for (int row = 0; row < 4; ++row) {
      if (measured_rows & (1u << row)) continue;
      residual(row) = 0.0;
      jacobian.row(row).setZero();
      if (with_covariance) {
        covariance.row(row).setZero();
        covariance.col(row).setZero();
        covariance(row, row) = 1.0;
      }
    }
  }
  // Makes this block (evaluated at another pose than the whitener of the feature it belongs to)
  // measure exactly `rows`, the rows that whitener was built for: possible when it measures all
  // of them (the extra rows are cleared); false when it lost one. (A lost row cannot be dropped
  // from a whitener with correlated rows: the remaining rows would get their conditional, not
  // their marginal, variance.)
  bool RestrictTo(unsigned rows) {
    if ((measured_rows & rows) != rows) return false;
    if (measured_rows != rows) {
      measured_rows = rows;
      ClearUnmeasuredRows(false);
    }
    return true;
  }
};

// A model's measurement covariance R: propagated from the endpoint noise through the residual,
// or the paper's fixed diagonal R.
enum class MeasurementNoise { kPropagated, kFixed };
inline EnumNames<MeasurementNoise> MeasurementNoiseNames() {
  return {{MeasurementNoise::kPropagated, "propagated"}, {MeasurementNoise::kFixed, "fixed"}};
}

// Validation-gate thresholds (eq. 20) by the number of residual rows a feature measures.
struct GateThresholds {
  double by_dimension[5] = {0.0, 0.0, 0.0, 0.0, 0.0};
  double operator()(const FeatureBlock& block) const { return by_dimension[block.Dimension()]; }
};

class FeatureModel {
 public:
  virtual ~FeatureModel() = default;

  virtual void Reset(const StereoRig& rig) = 0;
  // Makes `frame` the reference pair (I_1, I'_1). Returns the number of stereo-matched features
  // it holds that can be measured (not degenerate): the count a new reference pair compares
  // with.
  virtual int SetReference(const StereoFrame& frame) = 0;
  // Matches `frame` against the reference; features are then indexed 0 .. NumFeatures()-1.
  virtual int SetCurrent(const StereoFrame& frame) = 0;
  virtual int NumFeatures() const = 0;
  // Number of measurable stereo-matched features in the frame given to the last SetCurrent: what
  // SetReference would return for it, less the features a model places only weakly (those
  // LineTransferModel places by their endpoints), which a new reference is not taken for.
  virtual int CurrentStereoFeatures() const = 0;
  // Evaluates feature `index` at `cam_from_ref`, setting every field of `block` it is asked for
  // (measured_rows included). Returns false when the feature cannot be measured at this pose
  // (degenerate geometry); the block is then unspecified. A block with no measured row counts as
  // not measurable.
  virtual bool Evaluate(int index, const Rigid3d& cam_from_ref, bool with_covariance,
                        FeatureBlock* block) const = 0;
  // Called after each measured frame with the updated pose and the features of the update. A
  // model that refines its reference structure from past frames (the trifocal EKF's
  // reference refinement, issue 16) may do so here; it returns true and sets
  // *refined_cam_from_ref when the current pose is to move to the pose refined with it.
  virtual bool RefineStructure(const Rigid3d& /*cam_from_ref*/, const std::vector<int>& /*used*/,
                               Rigid3d* /*refined_cam_from_ref*/) {
    return false;
  }
  // After RefineStructure: a pose covariance *covariance the model derives from the
  // refinement's (its marginal of the current frame) and the filter's, `filter_covariance`
  // (both in the filter's left perturbation of cam_from_ref), and what it is for: kNone, nothing;
  // kFilter, the filter's pose covariance becomes it; kReport, the filter keeps its own and
  // only the reported covariance is widened to it, by the difference, until the next solve;
  // kReferencePlacement, *covariance is the reference pair's placement relative to its
  // structure (a left perturbation of the reference camera, in its frame): every pose measured
  // against that structure inherits it, so it is added to the reported covariance as the
  // reference pair's world covariance is, until a later solve gives another or a new reference
  // pair starts.
  enum class RefinedCovarianceUse { kNone, kFilter, kReport, kReferencePlacement };
  virtual RefinedCovarianceUse RefinedPoseCovariance(const Matrix6d& /*filter_covariance*/,
                                                     Matrix6d* /*covariance*/) const {
    return RefinedCovarianceUse::kNone;
  }

  // The error of the reference structure as "consider" parameters of a Schmidt filter
  // (structure_consider.h; issue 16). A model that describes it gives each of its reference
  // features s = 0 .. NumStructures()-1 a standard normal vector u_s (kStructureNoiseSize
  // entries, unused ones with zero Jacobian) that is fixed while the reference pair is kept, and
  // for feature `index` the Jacobian G = d r / d u of its residual; the covariance Evaluate
  // returns must then be R_current + G G^T, R_current the part of the noise that is new in every
  // frame. StructureVersion changes when the model replaces structure s's estimate (a refined
  // line): its error is then a new u_s.
  static constexpr int kStructureNoiseSize = 8;
  using StructureJacobian = Eigen::Matrix<double, 4, kStructureNoiseSize>;
  virtual bool DescribesStructure() const { return false; }
  virtual int NumStructures() const { return 0; }
  virtual int StructureOf(int /*index*/) const { return -1; }
  virtual int StructureVersion(int /*structure*/) const { return 0; }
  // False where Evaluate is false (rows left out by measured_rows: zero).
  virtual bool EvaluateStructureJacobian(int /*index*/, const Rigid3d& /*cam_from_ref*/,
                                         StructureJacobian* /*jacobian*/) const {
    return false;
  }
};

// A model whose features are matches of a reference feature with a current one (Match: a
// struct with the feature's `id`): feature i is matches_[i], rebuilt by each SetCurrent.
template <typename MatchType>
class MatchedFeatureModel : public FeatureModel {
 public:
  int NumFeatures() const override { return static_cast<int>(matches_.size()); }
  int CurrentStereoFeatures() const override { return current_stereo_; }
  // The id of feature `index` (for diagnostics and tests).
  std::int64_t FeatureId(int index) const { return matches_[index].id; }

 protected:
  using Match = MatchType;
  std::vector<Match> matches_;
  int current_stereo_ = 0;  // CurrentStereoFeatures()
};

}  // namespace slt
