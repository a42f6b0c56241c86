// The interface every tracker implements, and the registry that maps a method name to it.
//
// A tracker is given the stereo rig once, then one stereo frame of line observations at a
// time, and answers with the current pose of the left camera in the world (the left camera at
// the first frame), the covariance of that pose and a status. Trackers never return non-finite
// poses: when they cannot measure a frame, or cannot vouch for what they measured, they say so
// in the status and keep predicting.
//
// Adding a tracker: one folder under methods/ with a library target, plus one line in
// methods/registry.cc. The shared suite in tests/tracker_suite_test.cc and every experiment
// pick it up from the registry.
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/options.h"
#include "dataset/stereo_sequence.h"
#include "geometry/rigid3.h"
#include "geometry/se3.h"

namespace slt {

enum class TrackingStatus {
  kTracking,       // the frame was measured and the pose updated
  kNewReference,   // a new reference pair starts here (the first frame, or too few features left)
  kLost,           // too few usable features: the pose is a prediction only
  kDegraded,       // measured, but the tracker cannot vouch for the pose: the measurements
                   // disagree with each other or with the prediction beyond their noise, or
                   // under half of them agree with it (MinorityAgrees; docs/formats.md, status)
};

inline const char* TrackingStatusName(TrackingStatus status) {
  switch (status) {
    case TrackingStatus::kTracking: return "tracking";
    case TrackingStatus::kNewReference: return "new_reference";
    case TrackingStatus::kLost: return "lost";
    case TrackingStatus::kDegraded: return "degraded";
  }
  return "unknown";
}

constexpr int kNumTrackingStatuses = 4;

// Why a frame has the status it has (kNone: tracking normally).
enum class StatusReason {
  kNone,
  kFirstFrame,          // new reference: the first frame defines the world
  kFewFeaturesLeft,     // new reference: fewer reference features left than min_features
  kFeatureFractionLeft, // new reference: fewer left than min_feature_fraction of the reference's
                        // (or than refresh_fraction, with refresh_gain times as many in the frame)
  kFewMeasurable,       // lost: fewer than two features matched in both images and measurable
  kFewInsideGate,       // lost: fewer than two measurable features inside the gate (eq. 20)
  kNoUpdate,            // lost: the update found no solution or re-gating left fewer than two
  kNonFinite,           // lost: the state became non-finite; restarted from the last good pose
  kUnconstrained,       // lost: the features used do not measure every direction of the pose
  kFewAgree,            // lost: under a quarter of the measurable features agree with the pose
};
inline constexpr int kNumStatusReasons = 10;

inline const char* StatusReasonName(StatusReason reason) {
  switch (reason) {
    case StatusReason::kNone: return "";
    case StatusReason::kFirstFrame: return "first_frame";
    case StatusReason::kFewFeaturesLeft: return "few_features_left";
    case StatusReason::kFeatureFractionLeft: return "feature_fraction_left";
    case StatusReason::kFewMeasurable: return "few_measurable";
    case StatusReason::kFewInsideGate: return "few_inside_gate";
    case StatusReason::kNoUpdate: return "no_update";
    case StatusReason::kNonFinite: return "non_finite";
    case StatusReason::kUnconstrained: return "unconstrained";
    case StatusReason::kFewAgree: return "few_agree";
  }
  return "unknown";
}

// A frame whose pose fewer than this fraction of its measurable features agree with is
// reported lost (reason kFewAgree): when every segment is an outlier, a few of them still fit
// some pose by chance, and that pose is no measurement of the camera (issue 21).
inline constexpr double kMinAgreeingFraction = 0.25;
inline bool FewAgree(int agreeing, int measurable) { return agreeing < kMinAgreeingFraction * measurable; }

// A frame whose pose fewer than half of its measurable features agree with, not lost by FewAgree,
// is reported degraded: the pose rests on a minority of what the frame sees, and a handful of
// lines that happen to fit a drifting pose carry it while the rest fall outside the gate
// (docs/frontend.md, nineteenth pass).
inline bool MinorityAgrees(int agreeing, int measurable) { return 2 * agreeing < measurable; }

// An observed segment the trackers measure: finite and at least kMinSegmentLengthPx long (a
// shorter one fixes neither its line's direction nor the order of its endpoints).
inline constexpr double kMinSegmentLengthPx = 5.0;
inline bool UsableSegment(const Segment2d& segment) {
  return segment.allFinite() && SegmentLength(segment) >= kMinSegmentLengthPx;
}

// The policy every tracker shares on a frame without a usable measurement (status kLost): the
// velocity of its constant-velocity prediction is multiplied by lost_velocity_decay on every
// such frame; 1 = coast at constant velocity for ever, 0 = hold the last pose. Its one key is
// declared here, flat among each tracker's own options (OptionSchema::Flat).
struct LostFrameOptions {
  double lost_velocity_decay = 0.5;
};

inline const OptionSchema<LostFrameOptions>& LostFrameOptionsSchema() {
  static const OptionSchema<LostFrameOptions> schema = OptionSchema<LostFrameOptions>().Field(
      "lost_velocity_decay", &LostFrameOptions::lost_velocity_decay, InRange(0.0, 1.0),
      "velocity factor of the constant-velocity prediction per lost frame (1 = coast, 0 = hold)");
  return schema;
}

// A lost frame's pose for the trackers that keep a per-frame twist of their last measured
// motion (taylor_line_sfm, elqursh_three_line; the EKFs damp the velocity in their state,
// PoseVelocityFilter::DampVelocity): the twist is multiplied by the decay on every lost frame
// and applied on the left, cam_from_world <- exp(v) cam_from_world.
inline Rigid3d CoastAtConstantVelocity(const LostFrameOptions& lost, Vector6d* velocity,
                                       const Rigid3d& cam_from_world) {
  *velocity *= lost.lost_velocity_decay;
  return ExpSE3(*velocity) * cam_from_world;
}

struct TrackerOutput {
  Rigid3d cam_from_world;  // left camera at this frame; world = left camera at the first frame
  // Covariance of cam_from_world in the trackers' perturbation convention (docs/conventions.md):
  // true cam_from_world = ExpSE3(d) * cam_from_world, d = [translation; rotation] in the current
  // camera frame (metres, radians), d ~ N(0, covariance). Only meaningful when has_covariance;
  // a tracker without a covariance leaves it zero.
  Matrix6d covariance = Matrix6d::Zero();
  bool has_covariance = false;
  TrackingStatus status = TrackingStatus::kTracking;
  StatusReason reason = StatusReason::kNone;  // a lost frame's reason wins over a new reference's
  int features_available = 0;  // features with a usable measurement this frame
  int features_used = 0;       // features that passed the gate and entered the update
  // The reference pair's features left out of this frame's update, by reason (the trackers that
  // have a reference pair; with features_used they add up to the reference's feature count):
  int features_unmatched = 0;     // not observed (stereo-matched) in both images of this pair
  int features_degenerate = 0;    // observed, but no usable measurement (degenerate geometry)
  int features_outside_gate = 0;  // measurable, but outside the validation gate (eq. 20), the
                                  // robust start's consensus, or re-gated at the solution
};

// A run's frames added up, frame by frame: frames by status and by reason, and the tracker's
// feature counts summed over frames (track's summary, the experiments' per-trial metrics).
struct RunCounts {
  int frames = 0;
  int by_status[kNumTrackingStatuses] = {};
  int by_reason[kNumStatusReasons] = {};
  long features_used = 0;
  long features_available = 0;
  long features_unmatched = 0;
  long features_degenerate = 0;
  long features_outside_gate = 0;

  void Add(const TrackerOutput& out) {
    ++frames;
    ++by_status[static_cast<int>(out.status)];
    ++by_reason[static_cast<int>(out.reason)];
    features_used += out.features_used;
    features_available += out.features_available;
    features_unmatched += out.features_unmatched;
    features_degenerate += out.features_degenerate;
    features_outside_gate += out.features_outside_gate;
  }
  int Frames(TrackingStatus status) const { return by_status[static_cast<int>(status)]; }
  int Frames(StatusReason reason) const { return by_reason[static_cast<int>(reason)]; }
};

class PoseTracker {
 public:
  virtual ~PoseTracker() = default;

  // Starts a new sequence with this rig (clears every previous state). Throws
  // std::invalid_argument if the tracker cannot use the rig.
  virtual void Reset(const StereoRig& rig) = 0;
  // Processes the next frame. The first frame after Reset defines the world and returns the
  // identity with status kNewReference.
  virtual TrackerOutput Track(const StereoFrame& frame) = 0;
  // Options in effect, every default filled in (saved next to experiment results).
  virtual nlohmann::json Options() const = 0;

  // The pairing with an image front end (frontend/stereo_frontend.h, track_images): asked
  // after each Track() (and after Reset), whether the next frame should bring newly detected
  // and stereo-matched lines, under new ids, besides the lines tracked from the frames before.
  // Detection costs several times a tracked frame, so a tracker says yes only when it will use
  // them: the stereo EKF trackers when their next frame may take a new reference pair (paper
  // Sec. 3.3; asked one frame ahead, since the frame a tracker switches on can only carry lines
  // detected before it), a frame-to-frame or window tracker when its live line count falls. The default,
  // yes on every frame, is always correct, only slower.
  virtual bool WantsNewFeatures() const { return true; }
  // Asked after each Track(), like WantsNewFeatures: the tracker's prediction of the left
  // camera's cam_from_world at the next frame, or nothing when it has none (the default). The
  // front end seeds its optical flow with the motion it implies (frontend/image_tracking.h;
  // real sequences with large motion, issue 19); without one it extrapolates the tracker's
  // last two poses.
  virtual std::optional<Rigid3d> PredictNext() const { return std::nullopt; }
};

struct TrackerInfo {
  std::string name;         // method name used on command lines and in configs
  std::string description;  // one line, with the paper it implements
  // Creates the tracker from a JSON options object (missing keys keep their defaults).
  // Throws ConfigError naming `where` and the key on invalid options.
  std::function<std::unique_ptr<PoseTracker>(const nlohmann::json& options, const std::string& where)> create;
  // True for trackers that only exist to test the plumbing (skipped by accuracy checks and
  // default sweeps).
  bool plumbing_only = false;
  // The fewest stereo-matched lines the method can work with (the "minimum number" column of
  // the paper's Table 1).
  int minimum_lines = 2;
  // True for methods that need "primitive configurations" (two parallel lines and a third
  // orthogonal to them, Elqursh & Elgammal), which the paper's random lines practically never
  // hold: the shared suite and bench_table1 give them paper scenes with part of the lines on
  // cuboids (scene.paper.cuboid_fraction) instead.
  bool needs_primitive_configurations = false;
  // Every option with its default, allowed values and doc (`track --list-options`), derived
  // from the option schemas; unset: the tracker takes no options.
  std::function<std::vector<OptionDoc>()> list_options;
};

// One frame of a run: the tracker's output, the wall time of its Track() call and the frame's
// time stamp (StereoFrame::time), which pairs the output with the ground truth.
struct TrackedFrame {
  TrackerOutput output;
  double time_us = 0.0;
  double frame_time = 0.0;
};
// One Track() call, timed.
TrackedFrame TrackFrame(PoseTracker& tracker, const StereoFrame& frame);
// Resets `tracker` with the sequence's rig, then tracks every frame in order (TrackFrame): the
// loop that the experiment runner and the tests share (`track` streams its frames through
// TrackFrame).
std::vector<TrackedFrame> TrackSequence(PoseTracker& tracker, const StereoSequence& sequence);

// Every registered tracker, in registration order.
const std::vector<TrackerInfo>& RegisteredTrackers();
std::vector<std::string> RegisteredTrackerNames(bool include_plumbing = true);
// Throws std::invalid_argument listing the known names when `name` is not registered.
const TrackerInfo& FindTracker(const std::string& name);
std::unique_ptr<PoseTracker> CreateTracker(const std::string& name, const nlohmann::json& options = {},
                                           const std::string& where = "tracker options");

}  // namespace slt
