#include "methods/taylor_line_sfm/taylor_line_sfm_options.h"

namespace slt {

const OptionSchema<TaylorLineSfmOptions>& TaylorLineSfmOptionsSchema() {
  using O = TaylorLineSfmOptions;
  static const OptionSchema<O> schema =
      OptionSchema<O>()
          .Field("window_frames", &O::window_frames, AtLeast(0).Note("0 = every frame"),
                 "frames in the sliding window, the current one included")
          .Field("min_observation_frames", &O::min_observation_frames, AtLeast(1),
                 "frames of the window a line must be seen in to enter the problem")
          .Field("sigma_px", &O::sigma_px, Positive(), "expected rms distance of a segment to its line (px)")
          .Field("length_weighting", &O::length_weighting, "Taylor's weighting: each segment counts its length (px)")
          .Field("loss", &O::loss,
                 {{SegmentLoss::kNone, "none"}, {SegmentLoss::kHuber, "huber"}, {SegmentLoss::kCauchy, "cauchy"}},
                 "robust loss on (rms / sigma)^2")
          .Field("loss_scale", &O::loss_scale, Positive(), "scale of the robust loss (in sigma)")
          .Field("outlier_rms_sigma", &O::outlier_rms_sigma, AtLeast(0.0).Note("0 = never reject"),
                 "segments beyond this rms distance (in sigma) after a solve are rejected, the window solved again")
          .Field("min_plane_angle_deg", &O::min_plane_angle_deg, InRange(0.0, 90.0, "[)"),
                 "stereo pairs whose back-projected planes meet at a smaller angle are not triangulated")
          .Field("linear_solver", &O::linear_solver,
                 {{WindowLinearSolver::kDenseSchur, "dense_schur"}, {WindowLinearSolver::kSparseSchur, "sparse_schur"}},
                 "Ceres linear solver (lines eliminated first)")
          .Field("max_iterations", &O::max_iterations, AtLeast(1), "Levenberg-Marquardt iterations per solve at most")
          .Field("function_tolerance", &O::function_tolerance, AtLeast(0.0), "Ceres: relative cost change to stop at")
          .Field("gradient_tolerance", &O::gradient_tolerance, AtLeast(0.0), "Ceres: gradient norm to stop at")
          .Field("parameter_tolerance", &O::parameter_tolerance, AtLeast(0.0), "Ceres: relative step to stop at")
          .Field("threads", &O::threads, AtLeast(1), "Ceres threads (1 = deterministic)")
          .Flat(&O::lost, LostFrameOptionsSchema())
          .Check("window_frames", [](const O& o) {
            return o.window_frames == 1 ? std::string("must be 0 (every frame) or >= 2 (the oldest frame of the window is held fixed)")
                                        : std::string();
          });
  return schema;
}

void TaylorLineSfmOptions::Check(const std::string& where, const std::string& path) const {
  TaylorLineSfmOptionsSchema().Validate(*this, where, path);
}

}  // namespace slt
