#include "methods/stereo_ekf/stereo_ekf_options.h"

#include <cmath>

namespace slt {
namespace {

// Regularised lower incomplete gamma P(a, x): series below a + 1, Lentz continued fraction above.
double RegularizedGammaP(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_prefix = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 500 && std::abs(term) > 1e-17 * std::abs(sum); ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return sum * std::exp(log_prefix);
  }
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 500; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(log_prefix) * h;
}

}  // namespace

double ChiSquareQuantile(double probability, int dof) {
  const double k = dof;
  // Wilson-Hilferty start.
  const double z = std::sqrt(2.0) * [&] {
    // inverse erf via Newton on erf, from a rough start
    double y = 0.0;
    const double target = 2.0 * probability - 1.0;
    for (int i = 0; i < 100; ++i) {
      const double err = std::erf(y) - target;
      y -= err / (2.0 / std::sqrt(M_PI) * std::exp(-y * y));
      if (std::abs(err) < 1e-15) break;
    }
    return y;
  }();
  const double h = 2.0 / (9.0 * k);
  double x = std::max(1e-6, k * std::pow(1.0 - h + z * std::sqrt(h), 3.0));
  // Newton on the CDF.
  for (int i = 0; i < 50; ++i) {
    const double cdf = RegularizedGammaP(0.5 * k, 0.5 * x);
    const double log_pdf = (0.5 * k - 1.0) * std::log(x) - 0.5 * x - 0.5 * k * std::log(2.0) - std::lgamma(0.5 * k);
    const double step = (cdf - probability) / std::exp(log_pdf);
    x = std::max(0.5 * x, x - step);
    if (std::abs(step) < 1e-12 * x) break;
  }
  return x;
}

double StereoEkfOptions::GateThreshold(int dimension) const {
  return gate_threshold > 0.0 ? gate_threshold : ChiSquareQuantile(gate_probability, dimension);
}

void StereoEkfOptions::Check(const std::string& where, const std::string& path) const {
  auto fail = [&](const std::string& key, const std::string& why) {
    ThrowOptionError(where, path, key, why);
  };
  if (state != "velocity" && state != "pose_velocity") fail("state", "must be \"velocity\" or \"pose_velocity\"");
  if (integration != "exp" && integration != "first_order") fail("integration", "must be \"exp\" or \"first_order\"");
  if (!(accel_sigma_m > 0.0)) fail("accel_sigma_m", "must be > 0");
  if (!(accel_sigma_rad > 0.0)) fail("accel_sigma_rad", "must be > 0");
  if (!(initial_velocity_sigma_m > 0.0)) fail("initial_velocity_sigma_m", "must be > 0");
  if (!(initial_velocity_sigma_rad > 0.0)) fail("initial_velocity_sigma_rad", "must be > 0");
  if (max_iterations < 1 || max_iterations > 50) fail("max_iterations", "must be in [1, 50]");
  if (!(iteration_tolerance >= 0.0)) fail("iteration_tolerance", "must be >= 0");
  if (!(gate_probability > 0.0 && gate_probability < 1.0)) fail("gate_probability", "must be in (0, 1)");
  if (!(gate_threshold >= 0.0)) fail("gate_threshold", "must be >= 0 (0 = use gate_probability)");
  if (!(noise_adaptation_rate > 0.0 && noise_adaptation_rate <= 1.0)) fail("noise_adaptation_rate", "must be in (0, 1]");
  if (!(min_noise_scale > 0.0)) fail("min_noise_scale", "must be > 0");
  if (!(max_noise_scale >= min_noise_scale)) fail("max_noise_scale", "must be >= min_noise_scale");
  if (robust_start_frames < 0) fail("robust_start_frames", "must be >= 0");
  if (!(min_inlier_fraction >= 0.0 && min_inlier_fraction <= 1.0)) fail("min_inlier_fraction", "must be in [0, 1]");
  if (!(max_normalized_cost > 0.0)) fail("max_normalized_cost", "must be > 0");
  if (ransac_max_iterations < 1) fail("ransac_max_iterations", "must be >= 1");
  if (!(ransac_confidence > 0.0 && ransac_confidence < 1.0)) fail("ransac_confidence", "must be in (0, 1)");
  if (min_consensus < 2) fail("min_consensus", "must be >= 2");
  if (!(lost_velocity_decay >= 0.0 && lost_velocity_decay <= 1.0)) fail("lost_velocity_decay", "must be in [0, 1]");
  if (count_features != "measurable" && count_features != "gated") {
    fail("count_features", "must be \"measurable\" or \"gated\"");
  }
  if (min_features < 2) fail("min_features", "must be >= 2 (two features over-determine the pose)");
  if (!(min_feature_fraction >= 0.0 && min_feature_fraction <= 1.0)) fail("min_feature_fraction", "must be in [0, 1]");
}

void ApplyPaperPreset(StereoEkfOptions* o) {
  o->state = "velocity";
  o->max_iterations = 1;
  o->robust = false;
  o->adaptive_noise = false;
  o->min_feature_fraction = 0.0;
  o->count_features = "gated";
  o->lost_velocity_decay = 1.0;
}

void ReadStereoEkfOptions(JsonReader& r, StereoEkfOptions* o) {
  r.Get("state", &o->state)
      .Get("integration", &o->integration)
      .Get("accel_sigma_m", &o->accel_sigma_m)
      .Get("accel_sigma_rad", &o->accel_sigma_rad)
      .Get("initial_velocity_sigma_m", &o->initial_velocity_sigma_m)
      .Get("initial_velocity_sigma_rad", &o->initial_velocity_sigma_rad)
      .Get("max_iterations", &o->max_iterations)
      .Get("iteration_tolerance", &o->iteration_tolerance)
      .Get("gate_probability", &o->gate_probability)
      .Get("gate_threshold", &o->gate_threshold)
      .Get("adaptive_noise", &o->adaptive_noise)
      .Get("noise_adaptation_rate", &o->noise_adaptation_rate)
      .Get("min_noise_scale", &o->min_noise_scale)
      .Get("max_noise_scale", &o->max_noise_scale)
      .Get("robust", &o->robust)
      .Get("robust_start_frames", &o->robust_start_frames)
      .Get("min_inlier_fraction", &o->min_inlier_fraction)
      .Get("max_normalized_cost", &o->max_normalized_cost)
      .Get("ransac_max_iterations", &o->ransac_max_iterations)
      .Get("ransac_confidence", &o->ransac_confidence)
      .Get("seed", &o->seed)
      .Get("min_consensus", &o->min_consensus)
      .Get("lost_velocity_decay", &o->lost_velocity_decay)
      .Get("min_features", &o->min_features)
      .Get("min_feature_fraction", &o->min_feature_fraction)
      .Get("count_features", &o->count_features);
  o->Check(r.where(), r.path());
}

nlohmann::json StereoEkfOptionsToJson(const StereoEkfOptions& o) {
  return {{"state", o.state},
          {"integration", o.integration},
          {"accel_sigma_m", o.accel_sigma_m},
          {"accel_sigma_rad", o.accel_sigma_rad},
          {"initial_velocity_sigma_m", o.initial_velocity_sigma_m},
          {"initial_velocity_sigma_rad", o.initial_velocity_sigma_rad},
          {"max_iterations", o.max_iterations},
          {"iteration_tolerance", o.iteration_tolerance},
          {"gate_probability", o.gate_probability},
          {"gate_threshold", o.gate_threshold},
          {"adaptive_noise", o.adaptive_noise},
          {"noise_adaptation_rate", o.noise_adaptation_rate},
          {"min_noise_scale", o.min_noise_scale},
          {"max_noise_scale", o.max_noise_scale},
          {"robust", o.robust},
          {"robust_start_frames", o.robust_start_frames},
          {"min_inlier_fraction", o.min_inlier_fraction},
          {"max_normalized_cost", o.max_normalized_cost},
          {"ransac_max_iterations", o.ransac_max_iterations},
          {"ransac_confidence", o.ransac_confidence},
          {"seed", o.seed},
          {"min_consensus", o.min_consensus},
          {"lost_velocity_decay", o.lost_velocity_decay},
          {"min_features", o.min_features},
          {"min_feature_fraction", o.min_feature_fraction},
          {"count_features", o.count_features}};
}

}  // namespace slt
