// The measurement side of the stereo EKF trackers: one model per feature type (lines in
// trifocal_line_ekf, points in yu_point_ekf), one shared filter (stereo_ekf_tracker.h).
//
// A model matches the features of a reference stereo pair (I_1, I'_1) with those of the
// current pair (I_t, I'_t) and, for a pose cam_from_ref = M_t of the current left camera,
// returns for each matched feature four residual scalars r(M_t) that vanish for noise-free
// data at the true pose, their Jacobian with respect to a pose perturbation
// M_t <- Exp(d) M_t (docs/conventions.md), and, when asked, their covariance under the
// measurement noise.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "dataset/stereo_sequence.h"
#include "geometry/rigid3.h"

namespace slt {

struct FeatureBlock {
  Eigen::Vector4d residual;
  Eigen::Matrix<double, 4, 6> jacobian;  // d residual / d delta
  Eigen::Matrix4d covariance;            // filled only when asked for
};

class FeatureModel {
 public:
  virtual ~FeatureModel() = default;

  virtual void Reset(const StereoRig& rig) = 0;
  // Makes `frame` the reference pair (I_1, I'_1). Returns the number of stereo-matched features
  // it holds that can be measured (not degenerate): the count feature replacement compares
  // with.
  virtual int SetReference(const StereoFrame& frame) = 0;
  // Matches `frame` against the reference; features are then indexed 0 .. NumFeatures()-1.
  virtual int SetCurrent(const StereoFrame& frame) = 0;
  virtual int NumFeatures() const = 0;
  // Number of measurable stereo-matched features in the frame given to the last SetCurrent: what
  // SetReference would return for it.
  virtual int CurrentStereoFeatures() const = 0;
  // Evaluates feature `index` at `cam_from_ref`. Returns false when the feature cannot be
  // measured at this pose (degenerate geometry); the block is then unspecified.
  virtual bool Evaluate(int index, const Rigid3d& cam_from_ref, bool with_covariance,
                        FeatureBlock* block) const = 0;
};

}  // namespace slt
