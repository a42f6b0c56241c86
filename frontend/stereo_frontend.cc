#include "frontend/stereo_frontend.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "frontend/line_motion.h"
#include "frontend/parallel_edges.h"

namespace slt {
namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

StereoFrontEnd::StereoFrontEnd(const FrontEndOptions& options, const StereoRig& rig)
    : options_(options),
      rig_(rig),
      detector_(MakeLineDetector(options.detection)),
      matcher_(options.matching, rig),
      flow_{LineFlowTracker(options.tracking, 1), LineFlowTracker(options.tracking, 2)},
      earlier_(options.matching.max_previous_px > 0.0 ? options.matching.previous_pairs : 0),
      later_from_earlier_(earlier_.size()) {}

const StereoFrame& StereoFrontEnd::Process(const cv::Mat& left, const cv::Mat& right, double time,
                                           bool detect_new_lines, const std::optional<Rigid3d>& predicted_motion,
                                           const std::optional<Rigid3d>& measured_motion) {
  for (const cv::Mat* image : {&left, &right}) {
    if (image->type() != CV_8UC1 || image->cols != rig_.width || image->rows != rig_.height) {
      throw std::invalid_argument("front end: expected 8-bit grey images of " + std::to_string(rig_.width) + " x " +
                                  std::to_string(rig_.height) + ", got " + std::to_string(image->cols) + " x " +
                                  std::to_string(image->rows) + " with " + std::to_string(image->channels()) +
                                  " channel(s)");
    }
  }
  stats_ = FrontEndFrameStats();
  const Clock::time_point t0 = Clock::now();
  const int levels = options_.motion.unpredicted_pyramid_levels;
  flow_[0].BuildPyramid(left, &current_[0], levels);
  flow_[1].BuildPyramid(right, &current_[1], levels);
  stats_.times.track += Since(t0);
  lost_.clear();
  if (!earlier_.empty()) later_from_earlier_[0] = measured_motion;
  // New lines verified by the measured motion: detected and matched in the previous pair,
  // checked against the pairs before it, then tracked into this pair with the live lines.
  checks_.clear();
  if (detect_new_lines && started_ && options_.matching.max_previous_px > 0.0) {
    Rigid3d previous_from_earlier;
    for (int h = 0; h < earlier_stored_ && later_from_earlier_[h].has_value(); ++h) {
      previous_from_earlier = previous_from_earlier * *later_from_earlier_[h];
      checks_.push_back({{earlier_[h][0][1], earlier_[h][1][1]}, previous_from_earlier.Inverse()});
    }
  }
  const bool lagged = !checks_.empty();
  if (lagged) {
    DetectAndMatch(previous_[0][0], previous_[1][0], previous_, checks_, true);
    stats_.detection_lag = 1;
    AddNewLines();
  }
  if (started_) Track(predicted_motion);
  const int before = static_cast<int>(stats_.tracked + stats_.lost());
  stats_.rematch = started_ && before > 0 && stats_.tracked < options_.motion.rematch_below_fraction * before;
  const bool detect_here = (detect_new_lines && !lagged) || !started_;
  if (detect_here || stats_.rematch) {
    // Verified, when asked, against the previous pair by the predicted motion.
    checks_.clear();
    if (started_ && predicted_motion.has_value()) {
      checks_.push_back({{previous_[0][1], previous_[1][1]}, predicted_motion->Inverse()});
    }
    DetectAndMatch(left, right, current_, checks_, false);
    stats_.detection_lag = 0;
  }
  if (stats_.rematch) Rematch();
  if (detect_here) AddNewLines();
  // earlier <- previous <- current, the oldest buffers reused for the next pair.
  if (!earlier_.empty()) {
    if (started_) {
      std::rotate(earlier_.rbegin(), earlier_.rbegin() + 1, earlier_.rend());
      std::rotate(later_from_earlier_.rbegin(), later_from_earlier_.rbegin() + 1, later_from_earlier_.rend());
      std::swap(earlier_[0], previous_);
      later_from_earlier_[0].reset();
      earlier_stored_ = std::min(earlier_stored_ + 1, static_cast<int>(earlier_.size()));
    }
  }
  std::swap(previous_, current_);
  started_ = true;

  frame_.time = time;
  frame_.left.resize(live_.size());
  frame_.right.resize(live_.size());
  for (size_t i = 0; i < live_.size(); ++i) {
    frame_.left[i] = {live_[i].id, live_[i].left};
    frame_.right[i] = {live_[i].id, live_[i].right};
  }
  stats_.live = static_cast<int>(live_.size());
  return frame_;
}

void StereoFrontEnd::Track(const std::optional<Rigid3d>& predicted_motion) {
  const int n = static_cast<int>(live_.size());
  Clock::time_point t0 = Clock::now();
  // Seeds: the predicted camera motion through the line's 3-D line; else the line's last image
  // motion; else (a new line the pair cannot place) the predicted motion of a fronto-parallel
  // plane at the median depth of the placed lines, or nothing.
  const MotionOptions& motion = options_.motion;
  const bool use_camera = motion.seed == FlowSeed::kPrediction && predicted_motion.has_value();
  const double epipolar_sine = std::sin(options_.matching.epipolar_angle_deg * M_PI / 180.0);
  const StereoGeometry& geometry = matcher_.geometry();
  from_prediction_.assign(n, 0);
  depths_.clear();
  for (int c = 0; c < 2; ++c) {
    segments_[c].resize(n);
    maps_[c].assign(n, Eigen::Matrix3d::Identity());
  }
  unplaced_.clear();
  for (int i = 0; i < n; ++i) {
    const LiveLine& line = live_[i];
    segments_[0][i] = line.left;
    segments_[1][i] = line.right;
    StereoLineMaps maps;
    double depth = 0.0;
    // A line near the epipolar direction has no depth from the pair (its two back-projected
    // planes nearly coincide).
    if (use_camera && geometry.EpipolarSine(line.left) >= epipolar_sine &&
        PredictStereoLineMotion(rig_, *predicted_motion, line.left, line.right, kMinStereoPlaneSine, &maps, &depth)) {
      from_prediction_[i] = 1;
      depths_.push_back(depth);
    } else if (motion.seed != FlowSeed::kNone && line.has_shift) {
      maps.left = TranslationMap(line.shift[0]);
      maps.right = TranslationMap(line.shift[1]);
    } else {
      unplaced_.push_back(i);
      continue;
    }
    maps_[0][i] = maps.left;
    maps_[1][i] = maps.right;
  }
  if (use_camera && !unplaced_.empty()) {
    StereoLineMaps scene = RotationOnlyMaps(rig_, *predicted_motion);
    if (!depths_.empty()) {
      std::nth_element(depths_.begin(), depths_.begin() + depths_.size() / 2, depths_.end());
      scene = FrontoParallelMaps(rig_, *predicted_motion, depths_[depths_.size() / 2]);
    }
    for (const int i : unplaced_) {
      maps_[0][i] = scene.left;
      maps_[1][i] = scene.right;
    }
  }
  const int levels = use_camera ? options_.tracking.pyramid_levels : motion.unpredicted_pyramid_levels;
  for (int c = 0; c < 2; ++c) flow_[c].Flow(previous_[c], current_[c], segments_[c], maps_[c], levels);
  stats_.times.track += Since(t0);

  t0 = Clock::now();
  for (int c = 0; c < 2; ++c) flow_[c].Refit(rig_.width, rig_.height, &tracked_[c], &losses_[c]);
  int kept = 0;
  for (int i = 0; i < n; ++i) {
    const Segment2d& l = tracked_[0][i];
    const Segment2d& r = tracked_[1][i];
    // Lost in one image: dropped in both.
    LineLoss loss = losses_[0][i] != LineLoss::kKept ? losses_[0][i] : losses_[1][i];
    if (loss == LineLoss::kKept &&
        (geometry.BeamOverlap(l, r, epipolar_sine, options_.matching.epipolar_distance_px,
                              StereoGeometry::OverlapOf::kShorter, StereoGeometry::AlongEpipolar::kSameExtent) <
             options_.tracking.min_stereo_overlap ||
         !geometry.DisparityInRange(l, r, options_.matching.min_disparity_px, options_.matching.max_disparity_px))) {
      loss = LineLoss::kStereo;
    }
    if (loss != LineLoss::kKept) {
      ++stats_.lost_by[static_cast<int>(loss)];
      if (motion.rematch_below_fraction > 0.0) {
        LostLine lost{live_[i], {live_[i].left, live_[i].right}, from_prediction_[i] != 0};
        for (int c = 0; c < 2; ++c) {
          Segment2d mapped;
          if (MapSegment(maps_[c][i], segments_[c][i], &mapped)) lost.predicted[c] = mapped;
        }
        lost_.push_back(lost);
      }
      continue;
    }
    LiveLine& out = live_[kept];
    const LiveLine before = live_[i];
    out = {before.id, l, r};
    out.shift[0] = 0.5 * (l.head<2>() + l.tail<2>() - before.left.head<2>() - before.left.tail<2>());
    out.shift[1] = 0.5 * (r.head<2>() + r.tail<2>() - before.right.head<2>() - before.right.tail<2>());
    out.has_shift = true;
    stats_.predicted += from_prediction_[i];
    ++kept;
  }
  stats_.tracked = kept;
  live_.resize(kept);
  stats_.times.filter += Since(t0);
}

bool StereoFrontEnd::DuplicatesLiveLine(const Segment2d& segment, int c) const {
  const Eigen::Vector2d a = segment.head<2>(), b = segment.tail<2>();
  const Eigen::Vector2d d = (b - a).normalized();
  const double cos_max = std::cos(options_.duplicate_angle_deg * M_PI / 180.0);
  const double length = (b - a).norm();
  for (const LiveLine& live : live_) {
    const Segment2d& s = c == 0 ? live.left : live.right;
    if (!LiesAlong(s, segment, cos_max, options_.duplicate_distance_px)) continue;
    const double t0 = d.dot(s.head<2>() - a), t1 = d.dot(s.tail<2>() - a);
    if (std::max(t0, t1) > 0.0 && std::min(t0, t1) < length) return true;
  }
  return false;
}

void StereoFrontEnd::DetectAndMatch(const cv::Mat& left, const cv::Mat& right, const PyramidPair& pair,
                                    const std::vector<EarlierPair>& checks, bool assign_verified) {
  stats_.detected = true;
  Clock::time_point t0 = Clock::now();
  detections_[0] = DetectLines(*detector_, options_.detection, left);
  detections_[1] = DetectLines(*detector_, options_.detection, right);
  if (options_.detection.snap_detections) {
    for (int c = 0; c < 2; ++c) {
      SnapDetections(options_.tracking, options_.detection.min_length_px, pair[c][1], &detections_[c], &snap_);
    }
  }
  for (int c = 0; c < 2; ++c) {
    AddParallelEdges(options_.detection, options_.tracking.snap_min_gradient, c == 0 ? left : right, &detections_[c]);
  }
  if (!stats_.rematch) {
    // Detections on a live line would be dropped as duplicates after matching (AddNewLines):
    // neither described nor matched. Not when re-matching, which looks for lost lines among
    // all the detections.
    for (int c = 0; c < 2; ++c) {
      std::vector<ImageLine>& lines = detections_[c];
      lines.erase(std::remove_if(lines.begin(), lines.end(),
                                 [&](const ImageLine& line) { return DuplicatesLiveLine(line.segment, c); }),
                  lines.end());
    }
  }
  stats_.detected_left = static_cast<int>(detections_[0].size());
  stats_.detected_right = static_cast<int>(detections_[1].size());
  stats_.times.detect += Since(t0);

  t0 = Clock::now();
  for (int c = 0; c < 2; ++c) {
    msld_.SetImage(c == 0 ? left : right);
    descriptors_[c].resize(detections_[c].size());
    for (size_t i = 0; i < detections_[c].size(); ++i) msld_.Compute(detections_[c][i].segment, &descriptors_[c][i]);
  }
  stats_.times.describe += Since(t0);

  t0 = Clock::now();
  const bool verify = options_.matching.max_previous_px > 0.0 && !checks.empty();
  const auto seen_before = [&](int l, int r) {
    for (const EarlierPair& earlier : checks) {
      if (!SeenInPreviousPair(rig_, earlier.from_matched, detections_[0][l].segment, detections_[1][r].segment,
                              earlier.derivatives, options_.tracking, options_.matching.max_previous_px, &snap_)) {
        return false;
      }
    }
    return true;
  };
  const StereoMatcher::PairCheck check = seen_before;
  matcher_.Match(left, right, detections_[0], descriptors_[0], detections_[1], descriptors_[1], &matches_,
                 verify && assign_verified ? &check : nullptr);
  if (verify && !assign_verified) {
    matches_.erase(std::remove_if(matches_.begin(), matches_.end(),
                                  [&](const StereoMatch& m) { return !seen_before(m.left, m.right); }),
                   matches_.end());
  }
  stats_.matched = static_cast<int>(matches_.size());
  stats_.times.match += Since(t0);
}

void StereoFrontEnd::Rematch() {
  // The lost lines' descriptors, in the previous left image (level 0 of its pyramid).
  Clock::time_point t0 = Clock::now();
  const MotionOptions& motion = options_.motion;
  msld_.SetImage(previous_[0][0]);
  queries_.clear();
  std::vector<int> query_line;
  for (int i = 0; i < static_cast<int>(lost_.size()); ++i) {
    FrameMatchQuery query;
    if (!msld_.Compute(lost_[i].line.left, &query.descriptor)) continue;
    query.predicted = lost_[i].predicted[0];
    query.gate_px = motion.rematch_distance_px * (lost_[i].from_prediction ? 1.0 : motion.unpredicted_gate_scale);
    queries_.push_back(query);
    query_line.push_back(i);
  }
  stats_.times.describe += Since(t0);

  t0 = Clock::now();
  candidates_.resize(matches_.size());
  candidate_descriptors_.resize(matches_.size());
  for (size_t m = 0; m < matches_.size(); ++m) {
    candidates_[m] = detections_[0][matches_[m].left].segment;
    candidate_descriptors_[m] = descriptors_[0][matches_[m].left];
  }
  const FrameMatchGates gates{motion.rematch_angle_deg, options_.matching.max_msld_distance, options_.matching.msld_ratio};
  MatchAcrossFrames(gates, queries_, candidates_, candidate_descriptors_, &frame_matches_);
  for (const FrameMatch& fm : frame_matches_) {
    const LostLine& lost = lost_[query_line[fm.query]];
    const Segment2d& right = detections_[1][matches_[fm.candidate].right].segment;
    // The stereo partner must be where the line is predicted in the right image too.
    if (!InsidePredictionGate(lost.predicted[1], right, motion.rematch_angle_deg, queries_[fm.query].gate_px)) continue;
    live_.push_back({lost.line.id, candidates_[fm.candidate], right});
    ++stats_.rematched;
  }
  stats_.times.match += Since(t0);
}

void StereoFrontEnd::AddNewLines() {
  const Clock::time_point t0 = Clock::now();
  // Longest first, so that max_new_lines keeps the best-conditioned lines.
  std::sort(matches_.begin(), matches_.end(), [&](const StereoMatch& x, const StereoMatch& y) {
    return detections_[0][x.left].Length() > detections_[0][y.left].Length();
  });
  const size_t live_before = live_.size();
  for (const StereoMatch& m : matches_) {
    if (options_.max_new_lines > 0 && static_cast<int>(live_.size() - live_before) >= options_.max_new_lines) break;
    const Segment2d& l = detections_[0][m.left].segment;
    if (DuplicatesLiveLine(l)) continue;
    live_.push_back({next_id_++, l, detections_[1][m.right].segment});
  }
  stats_.added = static_cast<int>(live_.size() - live_before);
  stats_.times.match += Since(t0);
}

}  // namespace slt
