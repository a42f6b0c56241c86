// Taylor & Kriegman's image error of a line segment (C.J. Taylor, D.J. Kriegman, "Structure and
// motion from line segments in multiple images", IEEE PAMI 17(11), 1995) as a Ceres residual
// block with analytic Jacobians.
//
// A 3-D line L = [n; d] (world frame, line_sfm_manifolds.h) seen by a camera with
// camera_from_world = C * T (T the left camera's cam_from_world, C = I for the left camera and
// the rig's right_from_left for the right one) projects to the normalised image line
// l = moment of (C T) L (geometry/plucker.h), i.e. to the pixel line K^-T l. With h1, h2 the
// signed pixel distances of the observed segment's endpoints x1, x2 to it and ell the segment's
// length, the squared distance along the segment is linear-interpolated, and its integral is
//     E = integral_0^ell h(s)^2 ds = (ell / 3) (h1^2 + h1 h2 + h2^2)          (Taylor's error)
//       = ell * rms^2,    rms^2 = (h1^2 + h1 h2 + h2^2) / 3 the mean squared distance.
// Since h1^2 + h1 h2 + h2^2 = (h1 + h2/2)^2 + (sqrt(3)/2 h2)^2, E is the squared norm of a
// 2-vector, and the residual block is
//     r = sqrt(w / 3) / sigma * [h1 + h2 / 2;  sqrt(3)/2 h2],   |r|^2 = w rms^2 / sigma^2,
// w = ell (Taylor's length weighting: |r|^2 = E / sigma^2) or w = 1 (every segment counts
// once), sigma the expected rms distance of a segment (px): costs are in standard deviations
// squared, per pixel of segment length when weighted.
//
// The same block can instead hold the endpoints' distances themselves (SegmentResidual::kEndpoints),
//     r = sqrt(w) / sigma * [h1; h2],   |r|^2 = w (h1^2 + h2^2) / sigma^2,
// the likelihood's residual when the two endpoints' noise across the line is independent with
// standard deviation sigma. Taylor's form weighs a tilt of the line about the segment's middle
// (h1 = -h2) a third of an offset (h1 = h2) at equal distances; the endpoint form weighs both
// as the endpoints measure them.
//
// Jacobians are with respect to the ambient parameters (T as [R; t], 12 numbers; L as [n; d]);
// Ceres chains them with the manifolds' PlusJacobian. l is linear in R, t (through
// n_c = R n + t x R d) and in L, so the ambient Jacobian is exact and costs a few 2x3 products.
#pragma once

#include <ceres/loss_function.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "geometry/line2d.h"
#include "optim/line_sfm_manifolds.h"

namespace slt {

// What a residual needs to know of the camera it is measured in; one per camera of the rig,
// shared by all its residuals.
struct SegmentCamera {
  Eigen::Matrix3d pixel_from_normalized = Eigen::Matrix3d::Identity();  // K^-T, for lines
  bool is_left = true;
  // l = a n_c + b d_c for the line (n_c, d_c) in the left camera: a = R_C, b = [t_C]_x R_C.
  Eigen::Matrix3d a = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d b = Eigen::Matrix3d::Zero();

  // The left camera of `rig` (left = true) or its right camera.
  static SegmentCamera FromRig(const StereoRig& rig, bool left);
};

enum class SegmentResidual { kTaylor, kEndpoints };

class TaylorSegmentCost final : public ceres::SizedCostFunction<2, kPoseAmbientSize, kLineAmbientSize> {
 public:
  TaylorSegmentCost() = default;
  // `camera` must outlive the cost's use. `weight` is w above (ell or 1).
  void Set(const SegmentCamera* camera, const Segment2d& segment, double weight, double sigma_px,
           SegmentResidual form = SegmentResidual::kTaylor);

  // Parameters: the left camera's cam_from_world (PoseToParameters) and the line
  // (LineToParameters). Returns false where the line projects to no image line (it passes
  // through the camera centre).
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  const SegmentCamera* camera_ = nullptr;
  Eigen::Vector2d x1_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d x2_ = Eigen::Vector2d::Zero();
  double scale_ = 1.0;  // sqrt(w / 3) / sigma (Taylor), sqrt(w) / sigma (endpoints)
  // r = scale [h1 + mix h2; last h2]: (1/2, sqrt(3)/2) for Taylor's form, (0, 1) for the endpoints'.
  double mix_ = 0.5;
  double last_ = 0.8660254037844386;
};

// The robust loss of a segment whose residual carries the weight w: rho(s) = w rho_k(s / w),
// so that the robust decision is taken on (rms / sigma)^2 whatever the segment's length, while
// inliers keep Taylor's weighting. `robust` (e.g. ceres::HuberLoss(k), k in sigma) is not owned.
class WeightedSegmentLoss final : public ceres::LossFunction {
 public:
  void Set(const ceres::LossFunction* robust, double weight) {
    robust_ = robust;
    weight_ = weight;
  }
  void Evaluate(double s, double rho[3]) const override;

 private:
  const ceres::LossFunction* robust_ = nullptr;
  double weight_ = 1.0;
};

}  // namespace slt
