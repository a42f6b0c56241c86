#include "methods/stereo_ekf/stereo_ekf_options.h"

#include <cmath>

namespace slt {

double StereoEkfOptions::GateThreshold(int dimension) const { return ChiSquareQuantile(gate_probability, dimension); }

const OptionSchema<StereoEkfOptions>& StereoEkfOptionsSchema() {
  using O = StereoEkfOptions;
  static const OptionSchema<O> schema =
      OptionSchema<O>()
          .Field("state", &O::state, {{FilterState::kVelocity, "velocity"}, {FilterState::kPoseVelocity, "pose_velocity"}},
                 "filter state: the paper's velocity (eq. 10) or pose and velocity")
          .Field("integration", &O::integration, {{Integration::kExp, "exp"}, {Integration::kFirstOrder, "first_order"}},
                 "pose prediction: Exp(xi) M (eq. 11) or (I + Hat(xi)) M (eq. 12)")
          .Field("accel_sigma_m", &O::accel_sigma_m, Positive(), "velocity change per frame, m / frame^2 (eq. 18)")
          .Field("accel_sigma_rad", &O::accel_sigma_rad, Positive(), "velocity change per frame, rad / frame^2 (eq. 18)")
          .Field("initial_velocity_sigma_m", &O::initial_velocity_sigma_m, Positive(), "velocity prior at the start, m / frame")
          .Field("initial_velocity_sigma_rad", &O::initial_velocity_sigma_rad, Positive(),
                 "velocity prior at the start, rad / frame")
          .Field("adaptive_process_noise", &O::adaptive_process_noise,
                 "scale Q online from the pose corrections, between min_accel_sigma_m and accel_sigma_m")
          .Field("min_accel_sigma_m", &O::min_accel_sigma_m, Positive(),
                 "floor of the adapted process noise, m / frame^2 (rad in proportion)")
          .Field("max_iterations", &O::max_iterations, InRange(1, 50), "1 = the paper's EKF update; more = iterated EKF")
          .Field("iteration_tolerance", &O::iteration_tolerance, AtLeast(0.0),
                 "stop iterating below this step, in posterior standard deviations")
          .Field("gate_probability", &O::gate_probability, InRange(0.0, 1.0, "()"),
                 "validation gate (eq. 20): chi-square quantile of this probability")
          .Field("adaptive_noise", &O::adaptive_noise, "scale R online from the posterior residuals")
          .Field("robust", &O::robust, "RANSAC start when the prior is weak or the filter unhealthy")
          .Field("robust_start_frames", &O::robust_start_frames, AtLeast(0), "frames after the start seeded by RANSAC")
          .Field("robust_recheck", &O::robust_recheck,
                 "an update grossly inconsistent (cost over twice the healthy bound) is solved again from RANSAC on the same frame")
          .Flat(&O::ransac, RansacOptionsSchema())
          .Field("robust_max_sigma", &O::robust_max_sigma, AtLeast(0.0),
                 "RANSAC hypotheses move only along directions determined to this sigma (m or rad; 0 = all)")
          .Field("min_consensus", &O::min_consensus, AtLeast(2), "features a RANSAC solve needs to count")
          .Flat(&O::lost, LostFrameOptionsSchema())
          .Field("min_features", &O::min_features, AtLeast(2).Note("two features over-determine the pose"),
                 "new reference pair below this many remaining features (the paper's k_c)")
          .Field("min_feature_fraction", &O::min_feature_fraction, InRange(0.0, 1.0),
                 "new reference pair below this fraction of the reference's features")
          .Field("count_features", &O::count_features,
                 {{FeatureCount::kMeasurable, "measurable"}, {FeatureCount::kGated, "gated"}},
                 "remaining features: measurable, or also inside the gate (the paper's)")
          .Field("refresh_fraction", &O::refresh_fraction, InRange(0.0, 1.0),
                 "below this fraction of the reference's features, ask for new ones and switch once "
                 "refresh_gain times as many are in the frame (image input; 0 = off)")
          .Field("refresh_gain", &O::refresh_gain, AtLeast(1.0),
                 "a refresh switches when the frame holds this many times the remaining features")
          .Field("report_degraded", &O::report_degraded,
                 "status 'degraded' for a measured frame the tracker cannot vouch for")
          .Check("min_accel_sigma_m", [](const O& o) {
            return !o.adaptive_process_noise || o.min_accel_sigma_m <= o.accel_sigma_m
                       ? std::string()
                       : "must be at most accel_sigma_m (the ceiling) when adaptive_process_noise is true";
          });
  return schema;
}

void StereoEkfOptions::Check(const std::string& where, const std::string& path) const {
  StereoEkfOptionsSchema().Validate(*this, where, path);
}

void DisableRobustness(StereoEkfOptions* o) {
  o->robust = false;
  o->adaptive_noise = false;
  o->lost.lost_velocity_decay = 1.0;
}

void ApplyPaperPreset(StereoEkfOptions* o) {
  DisableRobustness(o);
  o->state = FilterState::kVelocity;
  o->max_iterations = 1;
  o->min_feature_fraction = 0.0;
  o->count_features = FeatureCount::kGated;
  // The paper's statuses: tracking, a new reference pair, lost.
  o->report_degraded = false;
}

void ReadStereoEkfOptions(JsonReader& r, StereoEkfOptions* o) { StereoEkfOptionsSchema().Read(r, o); }

nlohmann::json StereoEkfOptionsToJson(const StereoEkfOptions& o) { return StereoEkfOptionsSchema().ToJson(o); }

}  // namespace slt
