// Options of the stereo EKF shared by the trifocal-line and point trackers: state, motion
// model, update, gate, robustness and new reference pairs. Every field has a default; JSON
// keys are the field names.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "common/chi_square.h"  // ChiSquareQuantile, for the gate
#include "common/json_reader.h"
#include "common/options.h"
#include "methods/pose_tracker.h"
#include "optim/ransac.h"

namespace slt {

// The paper's state (eq. 10): the six velocities of the twist, the pose at t-1 taken as exact
// and the whole correction going into the velocity; or pose and velocity (12-D error state), so
// that a pose correction does not corrupt the velocity used by the next prediction.
enum class FilterState { kVelocity, kPoseVelocity };
// M_t = Exp(xi) M_{t-1} (eq. 11), or M_t = (I + Hat(xi)) M_{t-1} (eq. 12), re-orthonormalised.
enum class Integration { kExp, kFirstOrder };
// What the new-reference-pair test counts as remaining: the reference's features matched and not
// degenerate, or also inside the validation gate this frame (the paper's reading, where lines
// dropped by eq. 20 are not available).
enum class FeatureCount { kMeasurable, kGated };

// Every field's JSON key, range and one-line doc are declared once, in StereoEkfOptionsSchema()
// (stereo_ekf_options.cc); the comments here say why a field exists.
struct StereoEkfOptions {
  FilterState state = FilterState::kPoseVelocity;
  Integration integration = Integration::kExp;

  // Constant-velocity model (eq. 18): per-frame velocity change ~ N(0, diag(sigma^2)).
  double accel_sigma_m = 2e-3;     // m / frame^2
  double accel_sigma_rad = 4e-3;   // rad / frame^2
  // Velocity prior at the start (the velocity is unknown; the paper's protocol moves up to
  // 0.010 m and 1.2 deg per frame).
  double initial_velocity_sigma_m = 0.02;
  double initial_velocity_sigma_rad = 0.035;
  // Process noise adapted online (stereo_ekf_tracker.cc, AdaptProcessNoise): Q is multiplied by
  // q^2 in [(min_accel_sigma_m / accel_sigma_m)^2, 1], raised when the pose corrections are
  // larger than the predicted covariance expects and lowered when they are smaller. accel_sigma_*
  // are then the ceiling, min_accel_sigma_m the floor (the rotation's floor in proportion): the
  // floor also bounds how many frames the filter averages, which the reference structure's
  // error, correlated from frame to frame, requires (docs/long_sequences.md).
  bool adaptive_process_noise = false;
  double min_accel_sigma_m = 5e-5;  // m / frame^2

  // Update: 1 = the paper's single EKF update (eq. 19); more = iterated EKF (Gauss-Newton on
  // the MAP cost), stopping early when a step is shorter than iteration_tolerance posterior
  // standard deviations (its Mahalanobis length in the posterior information H + P^-1).
  int max_iterations = 2;
  double iteration_tolerance = 0.1;

  // Validation gate (eq. 20) r^T S^-1 r < g per feature, g the chi-square quantile of
  // gate_probability with as many degrees of freedom as the feature measures residual scalars
  // (4, or 2 for a line with one transfer degenerate). (The paper's g = 0.2 presumes an unstated
  // scaling of R.)
  double gate_probability = 0.999;

  // Measurement-noise scale: the model's covariances R are multiplied by s^2, estimated online
  // from the posterior residuals of the features in the gate (stereo_ekf_tracker.cc,
  // AdaptNoiseScale). The nominal noise (e.g. endpoint_sigma_px) then only sets the start;
  // noise-free data drive s to its minimum and the tracker becomes exact.
  bool adaptive_noise = true;

  // Robustness: a RANSAC over feature pairs seeds the update on the first robust_start_frames
  // frames after the start (weak velocity prior) and whenever the filter looks unhealthy
  // (stereo_ekf_tracker.h). If the robust solve then finds more inliers than the gate and
  // disagrees with the prediction, the filter is re-seeded from it.
  bool robust = true;
  int robust_start_frames = 3;
  // The same frame's recheck (with robust): an update whose posterior cost exceeds
  // kRecheckCostFactor (2) times its healthy bound is solved again from the RANSAC consensus of
  // that frame before the filter takes it. Its measurements disagree grossly (features the gate
  // let in that no pose explains: wrong 3-D lines of a new reference pair, stereo mismatches of
  // an image front end, docs/frontend.md); without the recheck the RANSAC runs only on the next
  // frame, after the filter has taken the polluted pose and velocity.
  bool robust_recheck = true;
  RansacOptions ransac;
  // The directions a RANSAC hypothesis and its consensus refinement solve (RefinePose,
  // least_squares.h): only those their features determine to this standard deviation or better
  // (m or rad); the others keep the start's value. Two vertical lines leave the height to their
  // noise, and a hypothesis that went anywhere in height explains every vertical line. 0 = every
  // direction (LDLT).
  double robust_max_sigma = 0.0;
  // A RANSAC solve counts only when at least min_consensus features agree (fewer when fewer are
  // measurable): any two features agree with the pose fitted to them, so a consensus of two out
  // of many confirms nothing.
  int min_consensus = 3;
  // On every frame without a usable update the velocity is pulled toward zero
  // (PoseVelocityFilter::DampVelocity; the trackers' common policy).
  LostFrameOptions lost;

  // New reference pair (Sec. 3.3, the paper's feature replacement): when fewer than min_features
  // (the paper's k_c) features of the reference remain, or fewer than min_feature_fraction of
  // those the reference started with, the current pair becomes the new reference.
  int min_features = 6;
  double min_feature_fraction = 0.5;
  FeatureCount count_features = FeatureCount::kMeasurable;
  // Refresh (for features from an image front end; 0 = off): when fewer than refresh_fraction of
  // the reference's features remain, ask the front end once for new ones (WantsNewFeatures), and
  // take the current pair as the new reference as soon as it holds at least refresh_gain times
  // the remaining ones. A front end loses tracks long before their lines leave the view and
  // detects only when asked, so without it a tracker runs on the dwindling survivors of its
  // reference while the view holds several times as many lines (docs/frontend.md). Off by
  // default: where every visible feature is observed on every frame (the synthetic protocol) it
  // only adds new reference pairs, each of which chains a pose error.
  double refresh_fraction = 0.0;
  double refresh_gain = 1.5;

  // Status kDegraded (methods/pose_tracker.h) for a frame whose update the tracker cannot vouch
  // for: the posterior cost above its chi-square bound (the measurements disagree with each other
  // or with the prediction), or fewer than half of the measurable features inside the gate
  // (pose_tracker.h MinorityAgrees). The next frame that passes both is kTracking again. A frame
  // whose measurements leave a direction of the pose unconstrained is lost whatever this says.
  bool report_degraded = true;

  double GateThreshold(int dimension = 4) const;  // the g in use for a feature of `dimension` rows
  // Throws ConfigError "<where>: key '<path>.<field>': ...".
  void Check(const std::string& where = "stereo EKF options", const std::string& path = "") const;
};

// Keys, ranges and docs of every field.
const OptionSchema<StereoEkfOptions>& StereoEkfOptionsSchema();

// The robustness policy beyond the paper (stereo_ekf_tracker.h, stages 2 and 4) switched off as
// a whole: no RANSAC start or re-seeding, no noise adaptation nor widening when lost, and
// constant-velocity prediction while nothing is measured (no velocity decay).
void DisableRobustness(StereoEkfOptions* options);
// The paper's filter (Sec. 3.3-4): 6-D velocity state, one EKF update, no robustness policy,
// new reference pairs counting the lines that survive the gate (eq. 20), no degraded status.
void ApplyPaperPreset(StereoEkfOptions* options);

// Reads the fields present in `reader` (keeps defaults for the others).
void ReadStereoEkfOptions(JsonReader& reader, StereoEkfOptions* options);
nlohmann::json StereoEkfOptionsToJson(const StereoEkfOptions& options);


}  // namespace slt
