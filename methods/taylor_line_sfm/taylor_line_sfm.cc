#include "methods/taylor_line_sfm/taylor_line_sfm.h"

#include "geometry/se3.h"

namespace slt {

TaylorLineSfmTracker::TaylorLineSfmTracker(const TaylorLineSfmOptions& options)
    : options_(options), window_(options) {}

void TaylorLineSfmTracker::Reset(const StereoRig& rig) {
  window_.Reset(rig);
  started_ = false;
  velocity_.setZero();
  counters_ = Counters();
  last_solve_ = WindowSolveReport();
}

TrackerOutput TaylorLineSfmTracker::Track(const StereoFrame& frame) {
  ++counters_.frames;
  std::vector<WindowObservation> left, right;
  CollectWindowObservations(frame.left, &sorted_, &left);
  CollectWindowObservations(frame.right, &sorted_, &right);
  TrackerOutput out;
  if (!started_) {
    started_ = true;
    window_.AddFrame(Rigid3d(), std::move(left), std::move(right));
    const TriangulationReport t = window_.TriangulateNewLines();
    counters_.lines_triangulated += t.triangulated;
    counters_.degenerate_triangulations += t.degenerate;
    out.status = TrackingStatus::kNewReference;
    out.reason = StatusReason::kFirstFrame;
    out.features_available = t.triangulated;
    known_lines_ = window_.NumLines();
    return out;
  }

  const Rigid3d previous = window_.Pose(0);
  window_.AddFrame(ExpSE3(velocity_) * previous, std::move(left), std::move(right));
  out.features_available = window_.KnownLinesInNewest();
  out.features_unmatched = std::max(0, known_lines_ - window_.KnownLinesInBothImagesOfNewest());
  last_solve_ = window_.Solve();
  const WindowSolveReport& s = last_solve_;
  counters_.lines_too_few_observations += s.newest_lines_too_few_observations;
  if (s.newest_in_problem) {
    ++counters_.solved_frames;
    counters_.solves += s.solves;
    counters_.iterations += s.iterations;
    counters_.solve_failures += !s.solved;
    counters_.rejected_observations += s.rejected_observations;
    counters_.dropped_lines += s.dropped_lines;
  }
  const bool solved = s.solved && s.newest_lines >= 2 && s.newest_observations >= 3;
  if (solved) {
    out.cam_from_world = window_.Pose(0);
    // The increment between the two newest frames as this solve left them.
    velocity_ = LogSE3(out.cam_from_world * window_.Pose(1).Inverse());
    out.status = TrackingStatus::kTracking;
    out.features_used = s.newest_lines;
    out.features_outside_gate = out.features_available - out.features_used;
    // Only the status: the solve's pose stands (as the EKFs do). Every line the frame sees is
    // judged at the solved pose, the ones too new for the solve too (they are independent
    // evidence); under half agreeing, the pose rests on a minority of what the frame sees.
    const int agreeing = window_.LinesAgreeingInNewest(options_.outlier_rms_sigma);
    if (FewAgree(agreeing, out.features_available)) {
      out.status = TrackingStatus::kLost;
      out.reason = StatusReason::kFewAgree;
      ++counters_.lost_frames;
    } else if (MinorityAgrees(agreeing, out.features_available)) {
      out.status = TrackingStatus::kDegraded;
      ++counters_.degraded_frames;
    }
  } else {
    out.cam_from_world = CoastAtConstantVelocity(options_.lost, &velocity_, previous);
    window_.SetNewestPose(out.cam_from_world);
    out.status = TrackingStatus::kLost;
    out.reason = out.features_available < 2 ? StatusReason::kFewMeasurable : StatusReason::kNoUpdate;
    out.features_outside_gate = out.features_available;
    ++counters_.lost_frames;
  }
  const TriangulationReport t = window_.TriangulateNewLines();
  counters_.lines_triangulated += t.triangulated;
  counters_.degenerate_triangulations += t.degenerate;
  if (solved) known_lines_ = window_.NumLines();
  return out;
}

TrackerInfo TaylorLineSfmInfo() {
  TrackerInfo info;
  info.name = "taylor_line_sfm";
  info.description = "Line structure from motion over a sliding window, Ceres (Taylor & Kriegman, IEEE PAMI 1995)";
  info.list_options = [] { return TaylorLineSfmOptionsSchema().Docs(); };
  info.create = [](const nlohmann::json& json, const std::string& where) -> std::unique_ptr<PoseTracker> {
    JsonReader reader(json, where);
    TaylorLineSfmOptions options;
    TaylorLineSfmOptionsSchema().Read(reader, &options);
    reader.RejectUnknownKeys();
    return std::make_unique<TaylorLineSfmTracker>(options);
  };
  // Two lines seen in two stereo frames determine the motion (8 residual scalars per frame).
  info.minimum_lines = 2;
  return info;
}

}  // namespace slt
