#include "optim/taylor_segment_cost.h"

#include <cmath>

#include "geometry/se3.h"

namespace slt {
namespace {

const double kHalfSqrt3 = 0.5 * std::sqrt(3.0);

}  // namespace

SegmentCamera SegmentCamera::FromRig(const StereoRig& rig, bool left) {
  SegmentCamera camera;
  camera.pixel_from_normalized = PixelFromNormalizedLineMatrix(left ? rig.left : rig.right);
  camera.is_left = left;
  if (!left) {
    // Moment of right_from_left * (n_c, d_c) (TransformPluecker).
    camera.a = rig.right_from_left.rotation;
    camera.b = Skew(rig.right_from_left.translation) * rig.right_from_left.rotation;
  }
  return camera;
}

void TaylorSegmentCost::Set(const SegmentCamera* camera, const Segment2d& segment, double weight, double sigma_px,
                            SegmentResidual form) {
  camera_ = camera;
  x1_ = segment.head<2>();
  x2_ = segment.tail<2>();
  const bool taylor = form == SegmentResidual::kTaylor;
  scale_ = std::sqrt(taylor ? weight / 3.0 : weight) / sigma_px;
  mix_ = taylor ? 0.5 : 0.0;
  last_ = taylor ? kHalfSqrt3 : 1.0;
}

bool TaylorSegmentCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const Eigen::Map<const Eigen::Matrix3d> rotation(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> translation(parameters[0] + 9);
  const Eigen::Map<const Eigen::Vector3d> moment(parameters[1]);
  const Eigen::Map<const Eigen::Vector3d> direction(parameters[1] + 3);

  // The line in the left camera (TransformPluecker), then in this camera, then in pixels.
  const Eigen::Vector3d direction_c = rotation * direction;
  const Eigen::Vector3d moment_c = rotation * moment + translation.cross(direction_c);
  const Eigen::Vector3d line =
      camera_->is_left ? moment_c : Eigen::Vector3d(camera_->a * moment_c + camera_->b * direction_c);
  const Eigen::Vector3d pixel_line = camera_->pixel_from_normalized * line;
  if (!(pixel_line.head<2>().squaredNorm() > 0.0)) return false;

  Eigen::Matrix<double, 1, 3> h1_d_line, h2_d_line;
  const bool want_jacobians = jacobians != nullptr && (jacobians[0] != nullptr || jacobians[1] != nullptr);
  const double h1 = SignedDistance(pixel_line, x1_, want_jacobians ? &h1_d_line : nullptr);
  const double h2 = SignedDistance(pixel_line, x2_, want_jacobians ? &h2_d_line : nullptr);
  residuals[0] = scale_ * (h1 + mix_ * h2);
  residuals[1] = scale_ * last_ * h2;
  if (!std::isfinite(residuals[0]) || !std::isfinite(residuals[1])) return false;
  if (!want_jacobians) return true;

  // G = d r / d l (normalised line), then through l = a n_c + b d_c and
  // n_c = R n + t x (R d), d_c = R d:
  //   d r / d n_c = G a =: GA,   d r / d d_c (all paths) = GA [t]_x + G b =: GC,
  //   d r / d R(:, j) = GA n_j + GC d_j,   d r / d t = -GA [d_c]_x,
  //   d r / d n = GA R,   d r / d d = GC R.
  Eigen::Matrix<double, 2, 3> g;
  g.row(0) = scale_ * (h1_d_line + mix_ * h2_d_line);
  g.row(1) = (scale_ * last_) * h2_d_line;
  g = g * camera_->pixel_from_normalized;
  Eigen::Matrix<double, 2, 3> ga, gc;
  if (camera_->is_left) {
    ga = g;
    gc = ga * Skew(translation);
  } else {
    ga = g * camera_->a;
    gc = ga * Skew(translation) + g * camera_->b;
  }
  if (jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 2, kPoseAmbientSize, Eigen::RowMajor>> j(jacobians[0]);
    for (int c = 0; c < 3; ++c) j.block<2, 3>(0, 3 * c) = ga * moment(c) + gc * direction(c);
    j.block<2, 3>(0, 9) = -ga * Skew(direction_c);
  }
  if (jacobians[1] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 2, kLineAmbientSize, Eigen::RowMajor>> j(jacobians[1]);
    j.block<2, 3>(0, 0) = ga * rotation;
    j.block<2, 3>(0, 3) = gc * rotation;
  }
  return true;
}

void WeightedSegmentLoss::Evaluate(double s, double rho[3]) const {
  if (robust_ == nullptr) {
    rho[0] = s;
    rho[1] = 1.0;
    rho[2] = 0.0;
    return;
  }
  robust_->Evaluate(s / weight_, rho);
  rho[0] *= weight_;
  rho[2] /= weight_;
}

}  // namespace slt
