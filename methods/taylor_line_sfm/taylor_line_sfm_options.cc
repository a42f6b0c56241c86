#include "methods/taylor_line_sfm/taylor_line_sfm_options.h"

namespace slt {

void TaylorLineSfmOptions::Check(const std::string& where, const std::string& path) const {
  auto fail = [&](const std::string& key, const std::string& why) { ThrowOptionError(where, path, key, why); };
  if (window_frames < 0 || window_frames == 1) {
    fail("window_frames", "must be 0 (every frame) or >= 2 (the oldest frame of the window is held fixed)");
  }
  if (min_observation_frames < 1) fail("min_observation_frames", "must be >= 1");
  if (!(sigma_px > 0.0)) fail("sigma_px", "must be > 0");
  if (loss != "none" && loss != "huber" && loss != "cauchy") fail("loss", "must be \"none\", \"huber\" or \"cauchy\"");
  if (!(loss_scale > 0.0)) fail("loss_scale", "must be > 0");
  if (!(outlier_rms_sigma >= 0.0)) fail("outlier_rms_sigma", "must be >= 0 (0 = never reject)");
  if (!(min_segment_length_px >= 0.0)) fail("min_segment_length_px", "must be >= 0");
  if (!(min_plane_angle_deg >= 0.0 && min_plane_angle_deg < 90.0)) fail("min_plane_angle_deg", "must be in [0, 90)");
  if (linear_solver != "dense_schur" && linear_solver != "sparse_schur") {
    fail("linear_solver", "must be \"dense_schur\" or \"sparse_schur\"");
  }
  if (max_iterations < 1) fail("max_iterations", "must be >= 1");
  if (!(function_tolerance >= 0.0)) fail("function_tolerance", "must be >= 0");
  if (!(gradient_tolerance >= 0.0)) fail("gradient_tolerance", "must be >= 0");
  if (!(parameter_tolerance >= 0.0)) fail("parameter_tolerance", "must be >= 0");
  if (threads < 1) fail("threads", "must be >= 1");
  if (!(lost_velocity_decay >= 0.0 && lost_velocity_decay <= 1.0)) fail("lost_velocity_decay", "must be in [0, 1]");
}

void ReadTaylorLineSfmOptions(JsonReader& r, TaylorLineSfmOptions* o) {
  r.Get("window_frames", &o->window_frames)
      .Get("min_observation_frames", &o->min_observation_frames)
      .Get("sigma_px", &o->sigma_px)
      .Get("length_weighting", &o->length_weighting)
      .Get("loss", &o->loss)
      .Get("loss_scale", &o->loss_scale)
      .Get("outlier_rms_sigma", &o->outlier_rms_sigma)
      .Get("min_segment_length_px", &o->min_segment_length_px)
      .Get("min_plane_angle_deg", &o->min_plane_angle_deg)
      .Get("linear_solver", &o->linear_solver)
      .Get("max_iterations", &o->max_iterations)
      .Get("function_tolerance", &o->function_tolerance)
      .Get("gradient_tolerance", &o->gradient_tolerance)
      .Get("parameter_tolerance", &o->parameter_tolerance)
      .Get("threads", &o->threads)
      .Get("lost_velocity_decay", &o->lost_velocity_decay);
  o->Check(r.where(), r.path());
}

nlohmann::json TaylorLineSfmOptionsToJson(const TaylorLineSfmOptions& o) {
  return {{"window_frames", o.window_frames},
          {"min_observation_frames", o.min_observation_frames},
          {"sigma_px", o.sigma_px},
          {"length_weighting", o.length_weighting},
          {"loss", o.loss},
          {"loss_scale", o.loss_scale},
          {"outlier_rms_sigma", o.outlier_rms_sigma},
          {"min_segment_length_px", o.min_segment_length_px},
          {"min_plane_angle_deg", o.min_plane_angle_deg},
          {"linear_solver", o.linear_solver},
          {"max_iterations", o.max_iterations},
          {"function_tolerance", o.function_tolerance},
          {"gradient_tolerance", o.gradient_tolerance},
          {"parameter_tolerance", o.parameter_tolerance},
          {"threads", o.threads},
          {"lost_velocity_decay", o.lost_velocity_decay}};
}

}  // namespace slt
