// The stereo EKF tracker shared by the trifocal-line tracker (paper Sec. 3-4) and Yu's point
// tracker: one filter, one FeatureModel per feature type.
//
// Track() runs each frame through five stages over one per-frame state (FrameState):
//   1. gate: predict (eq. 18: xi_t|t-1 = xi_t-1, M_t|t-1 = Exp(xi) M_t-1, pose_velocity_filter.h),
//      match the current pair with the reference pair, evaluate every matched feature at the
//      prediction (residual, Jacobian, covariance: the model's job) and apply the validation
//      gate (eq. 20): r^T (J P J^T + R)^-1 r < g per feature;
//   2. robust start: when the prior is weak (first frames) or the filter looks unhealthy, a
//      RANSAC over feature pairs (robust_pose_solver.h) seeds the update and its inlier set,
//      and re-seeds the filter if the prediction is inconsistent with it;
//   3. update (eq. 19) as an iterated EKF: Gauss-Newton on
//      sum_i |r_i(Exp(d) M)|^2_{R_i} + |d|^2_{P_pp}, one step = the paper's EKF update; when
//      the model describes its reference structure's error (FeatureModel::DescribesStructure),
//      each step is instead the Schmidt-Kalman update of structure_consider.h, which keeps the
//      state's correlation with that error. The filter takes the solution only after the
//      recheck (robust_recheck): a solution grossly inconsistent with its measurements (cost
//      over kRecheckCostFactor times the healthy bound of stage 4) is solved again from the
//      robust start of stage 2 on the same frame, if it had not run;
//   4. assess: lost (no update) or tracking; health (posterior cost against its chi-square
//      bound), the measurement-noise scale for the next frame and, when adapted, the process
//      noise (the pose correction against its expected size);
//   5. new reference pair (Sec. 3.3, the paper's feature replacement): when too few reference
//      features remain, the current pair becomes the reference and the world pose of the
//      reference is chained; a frame without an update or with a grossly inconsistent one
//      waits, unless fewer than min_features remain (docs/derivations.md).
// Stages 2 and 4 and the recheck hold the robustness policy beyond the paper (RANSAC start,
// recheck and re-seeding, health, noise adaptation, widening and velocity decay while lost);
// the paper preset turns it off as a whole (ApplyPaperPreset), and each part has its own option
// for ablations.
#pragma once

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "methods/pose_tracker.h"
#include "methods/stereo_ekf/feature_model.h"
#include "methods/stereo_ekf/least_squares.h"
#include "methods/stereo_ekf/pose_velocity_filter.h"
#include "methods/stereo_ekf/robust_pose_solver.h"
#include "methods/stereo_ekf/stereo_ekf_options.h"
#include "methods/stereo_ekf/structure_consider.h"

namespace slt {

class StereoEkfTracker : public PoseTracker {
 public:
  // `model_options` is the model's part of the options, echoed by Options().
  StereoEkfTracker(const StereoEkfOptions& options, std::unique_ptr<FeatureModel> model,
                   nlohmann::json model_options);

  void Reset(const StereoRig& rig) override;
  TrackerOutput Track(const StereoFrame& frame) override;
  nlohmann::json Options() const override;
  // True before the first frame and when too few features of the reference remain for the
  // next frame to keep it (the test of NewReferencePair without its "the current frame has
  // more features" part): the next frame then takes a new reference pair if it brings new
  // lines. (When the count falls below the threshold between two frames, the new reference
  // comes one frame later.) Also once per reference when fewer than filter.refresh_fraction of
  // its features remain (the refresh, stereo_ekf_options.h).
  bool WantsNewFeatures() const override { return !started_ || wants_new_features_; }
  // The motion model's prediction (eq. 18) of the next frame's pose, M_t+1|t = Exp(xi) M_t,
  // chained to the world: once a frame has been measured (before that the velocity is the
  // prior's zero, no prediction).
  std::optional<Rigid3d> PredictNext() const override;

  // Counters since Reset, for tests and diagnostics.
  struct Counters {
    int frames = 0;
    int new_references = 0;   // new reference pairs (not counting the first frame)
    int robust_solves = 0;    // RANSAC runs
    int reseeds = 0;          // filter re-seeded from a RANSAC solve
    int lost_frames = 0;
    int degraded_frames = 0;
    int updates = 0;            // measurement updates
    int update_iterations = 0;  // Gauss-Newton iterations over all updates (>= updates)
  };
  double noise_scale() const { return std::sqrt(noise_scale_sq_); }
  const Counters& counters() const { return counters_; }
  const PoseVelocityFilter& filter() const { return filter_; }
  const FeatureModel& model() const { return *model_; }

 private:
  // What the stages of one frame pass on; the features themselves are in features_, valid_
  // (measurable) and inliers_ (those entering the update).
  struct FrameState {
    Rigid3d predicted;
    // Features measurable, inside the gate at the prediction, and in the update.
    int valid = 0, gated = 0, used = 0;
    int entering = 0;  // features entering the update (after the robust start)
    Rigid3d linearization;                // where the update starts
    bool blocks_at_linearization = true;  // features_ were evaluated at `linearization`
    double cost = std::numeric_limits<double>::infinity();  // posterior cost; infinity: no update
    bool robust_solved = false;  // a RANSAC ran on this frame
    TrackerOutput out;
  };

  TrackerOutput Start(const StereoFrame& frame);
  // The stages, in order.
  void Gate(const StereoFrame& frame, FrameState* state);
  // `recheck`: run for an update found grossly inconsistent (stage 3), which its consensus then
  // replaces whatever its size. True when the consensus became the update's inlier set.
  bool RobustStart(FrameState* state, bool recheck = false);
  void Update(FrameState* state);
  // The recheck of stage 3 (robust_recheck), then the filter takes the update's solution.
  void RecheckAndCommit(FrameState* state);
  void Assess(FrameState* state);
  // Lets the model refine its reference structure (FeatureModel::RefineStructure) after a
  // measured frame, moves the pose where the model says, and takes the pose covariance the
  // model derives from its refinement (FeatureModel::RefinedPoseCovariance) into the filter or
  // into the reported covariance only.
  void RefineStructure(FrameState* state);
  void NewReferencePair(const StereoFrame& frame, FrameState* state);
  // Pose and covariance of the output in the world: cam_from_world = cam_from_ref *
  // ref_from_world, so with independent errors (left perturbations, docs/conventions.md)
  //   P_world = P_rel + Ad(cam_from_ref) P_ref_from_world Ad(cam_from_ref)^T,
  // P_rel the filter's pose covariance.
  void SetOutputPose(TrackerOutput* out) const;

  // Iterated update on `inliers_`, with the filter's pose as prior mean, starting at
  // `linearization`; `blocks_at_linearization` says that features_ were evaluated there.
  // Returns the posterior cost of the measurements (whitened, squared), or infinity when it
  // made no update (nothing solvable, or fewer than two features left after re-gating). The
  // solution waits in pending_ for CommitUpdate.
  double IteratedUpdate(const Rigid3d& linearization, bool blocks_at_linearization);
  // The filter takes pending_ (the last IteratedUpdate's solution).
  void CommitUpdate();
  // Drops the inliers whose linearised cost after `step` exceeds the gate; true if any.
  bool RemovePosteriorOutliers(const Vector6d& step);
  // `rows`: MeasuredRows() of this frame's update.
  void AdaptNoiseScale(int rows);
  // Options.adaptive_process_noise: scales Q from this frame's correction ratio (stereo_ekf_tracker.cc).
  void AdaptProcessNoise();
  // Residual scalars measured by the features of this frame's update (4 per feature, fewer for
  // a feature with rows left out).
  int MeasuredRows() const;
  // The healthy bound on the posterior cost of `rows` residual scalars.
  double HealthyCost(int rows);
  // This frame's update is grossly inconsistent with its measurements: its posterior cost is
  // over kRecheckCostFactor times HealthyCost (the recheck re-solves such a frame; it does not
  // become a new reference). Call only for a frame with an update (a finite cost).
  bool GrosslyInconsistent(double cost);

  StereoEkfOptions options_;
  std::unique_ptr<FeatureModel> model_;
  nlohmann::json model_options_;
  GateThresholds gate_;
  double median_scale_[5] = {0.0, 0.0, 0.0, 0.0, 0.0};  // median of chi-square(4) / chi-square(d)
  double reseed_gate_ = 0.0;  // chi-square, 6 dof
  std::vector<double> healthy_cost_;  // HealthyCost by rows, filled as needed

  bool started_ = false;
  bool velocity_measured_ = false;  // an update has informed the velocity since Start
  // Robustness policy state: the last frame's health and update size, the noise scale.
  bool healthy_ = true;
  bool wants_new_features_ = true;
  int previous_inliers_ = 0;
  double noise_scale_sq_ = 1.0;
  // This frame's pose correction over its expected size, and its running mean (process noise).
  double correction_ratio_ = 0.0;
  double correction_ratio_mean_ = 1.0;
  int frames_since_start_ = 0;
  int reference_features_ = 0;
  int remaining_before_ = 0;  // the reference's features counted on the last frame
  bool asked_ahead_ = false;  // new features were asked for ahead since the last reference
  bool asked_refresh_ = false;  // new features were asked for by the refresh since the last reference
  // Added to the reported pose covariance (FeatureModel::RefinedCovarianceUse::kReport) until
  // the next solve or a new reference pair; zero otherwise.
  Matrix6d reported_widening_ = Matrix6d::Zero();
  Rigid3d ref_from_world_;
  // Covariance of ref_from_world_ (the output covariance of the frame that became the
  // reference; zero for the first frame, which defines the world).
  Matrix6d ref_from_world_covariance_ = Matrix6d::Zero();
  // Covariance of the reference pair's placement relative to its structure
  // (FeatureModel::RefinedCovarianceUse::kReferencePlacement), reported like
  // ref_from_world_covariance_; zero otherwise.
  Matrix6d reference_placement_covariance_ = Matrix6d::Zero();
  // This frame's measurement information H = J^T R^-1 J at the accepted update (set by
  // IteratedUpdate): the measurements constrain every direction of the pose when it is positive
  // definite.
  Matrix6d frame_information_ = Matrix6d::Zero();
  PoseVelocityFilter filter_;
  // When the model describes its reference structure's error (FeatureModel::DescribesStructure):
  // the update treats it as consider parameters (structure_consider.h).
  std::unique_ptr<StructureConsider> consider_;
  RobustPoseSolver robust_solver_;
  Counters counters_;

  // Per-frame workspace, kept to avoid allocation in the hot path.
  std::vector<WeightedFeature> features_;
  std::vector<int> valid_;
  std::vector<int> inliers_;
  std::vector<double> posterior_costs_;
  SpdSolver6 prior_solver_;        // P_pp of this frame
  Matrix6d prior_information_;     // P_pp^-1
  std::vector<Rigid3d> starts_;
  RobustSolveResult robust_result_;
  // The solution of the last IteratedUpdate, not yet in the filter: the pose correction and its
  // posterior covariance, or with the structure consider the state correction and covariance.
  struct PendingUpdate {
    Vector6d delta = Vector6d::Zero();
    Matrix6d covariance = Matrix6d::Identity();
    StructureConsider::Vector12d consider_delta = StructureConsider::Vector12d::Zero();
    StructureConsider::Matrix12d consider_posterior = StructureConsider::Matrix12d::Identity();
    Matrix6d information = Matrix6d::Zero();  // H of its measurements
  };
  PendingUpdate pending_;
};

// A named starting point of a stereo EKF tracker's options ("preset" in its JSON), applied
// before the file's own values, which override it. "default" (the options' defaults) needs none.
template <typename MeasurementOptions>
struct StereoEkfPreset {
  std::string name;
  std::string doc;
  void (*apply)(StereoEkfOptions* filter, MeasurementOptions* measurement);
};

// "default" and the presets' names, each as `quote` + name + `quote`, joined by `separator`.
template <typename MeasurementOptions>
std::string PresetNames(const std::vector<StereoEkfPreset<MeasurementOptions>>& presets, const std::string& quote,
                        const std::string& separator) {
  std::string names = quote + "default" + quote;
  for (const StereoEkfPreset<MeasurementOptions>& p : presets) names += separator + quote + p.name + quote;
  return names;
}

// Creates a StereoEkfTracker from the options JSON every stereo EKF tracker takes:
//   {"preset": "default" | <a name of presets>, "filter": {StereoEkfOptions},
//    "measurement": {model options}}
// `read_measurement(JsonReader&, MeasurementOptions*)` reads and checks the model's part,
// `to_json` echoes it, `make_model(const MeasurementOptions&)` builds the model.
template <typename MeasurementOptions, typename ReadMeasurement, typename ToJson, typename MakeModel>
std::unique_ptr<PoseTracker> CreateStereoEkfTracker(const nlohmann::json& json, const std::string& where,
                                                    const std::vector<StereoEkfPreset<MeasurementOptions>>& presets,
                                                    ReadMeasurement read_measurement, ToJson to_json,
                                                    MakeModel make_model) {
  JsonReader reader(json, where);
  std::string preset = "default";
  reader.Get("preset", &preset);
  StereoEkfOptions filter;
  MeasurementOptions measurement;
  bool found = preset == "default";
  for (const StereoEkfPreset<MeasurementOptions>& p : presets) {
    if (p.name != preset) continue;
    p.apply(&filter, &measurement);
    found = true;
  }
  if (!found) reader.Fail("preset", "must be one of " + PresetNames(presets, "\"", ", "));
  JsonReader filter_reader = reader.Child("filter");
  ReadStereoEkfOptions(filter_reader, &filter);
  filter_reader.RejectUnknownKeys();
  JsonReader measurement_reader = reader.Child("measurement");
  read_measurement(measurement_reader, &measurement);
  measurement_reader.RejectUnknownKeys();
  reader.RejectUnknownKeys();
  return std::make_unique<StereoEkfTracker>(filter, make_model(measurement), to_json(measurement));
}

// The listing of the options CreateStereoEkfTracker reads (TrackerInfo::list_options): "preset",
// then "filter.*" and "measurement.*" with the default preset's values.
template <typename MeasurementOptions>
std::vector<OptionDoc> StereoEkfOptionDocs(const std::vector<StereoEkfPreset<MeasurementOptions>>& presets,
                                           const OptionSchema<MeasurementOptions>& measurement) {
  std::string doc = "the file's own values start from it";
  for (const StereoEkfPreset<MeasurementOptions>& p : presets) doc += "; \"" + p.name + "\": " + p.doc;
  std::vector<OptionDoc> docs = {{"preset", PresetNames(presets, "", " | "), "\"default\"", doc}};
  StereoEkfOptionsSchema().List(StereoEkfOptions(), "filter", &docs);
  measurement.List(MeasurementOptions(), "measurement", &docs);
  return docs;
}

// The TrackerInfo of a stereo EKF tracker on the measurement model `Model` (constructed from its
// MeasurementOptions): created by CreateStereoEkfTracker, listed by StereoEkfOptionDocs. What
// the trifocal-line and the point-trifocal EKF register.
template <typename Model, typename MeasurementOptions>
TrackerInfo StereoEkfTrackerInfo(std::string name, std::string description,
                                 std::vector<StereoEkfPreset<MeasurementOptions>> presets,
                                 void (*read_measurement)(JsonReader&, MeasurementOptions*),
                                 nlohmann::json (*to_json)(const MeasurementOptions&),
                                 const OptionSchema<MeasurementOptions>& (*schema)()) {
  TrackerInfo info;
  info.name = std::move(name);
  info.description = std::move(description);
  info.create = [=](const nlohmann::json& json, const std::string& where) {
    return CreateStereoEkfTracker<MeasurementOptions>(
        json, where, presets, read_measurement, to_json,
        [](const MeasurementOptions& m) { return std::make_unique<Model>(m); });
  };
  info.list_options = [schema, presets] { return StereoEkfOptionDocs(presets, schema()); };
  return info;
}

}  // namespace slt
