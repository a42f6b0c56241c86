#include "frontend/frontend_audit.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "common/random.h"
#include "frontend/image_sampling.h"
#include "simulator/random_draws.h"

namespace slt {
namespace {

void Intersect(const std::vector<int>& a, const std::vector<int>& b, std::vector<int>* out) {
  out->clear();
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(*out));
}

}  // namespace

ProjectedGroundTruth::ProjectedGroundTruth(const std::vector<Line3d>& lines_in_world, const AuditCriteria& criteria)
    : lines_(lines_in_world), criteria_(criteria), cos_max_(std::cos(criteria.max_angle_deg * M_PI / 180.0)) {}

void ProjectedGroundTruth::Project(const Rigid3d& cam_from_world, const PinholeCamera& camera, double min_depth_m) {
  projected_.assign(lines_.size(), Projected());
  for (size_t i = 0; i < lines_.size(); ++i) {
    Eigen::Vector3d p = cam_from_world * lines_[i].p, q = cam_from_world * lines_[i].q;
    if (p.z() < min_depth_m && q.z() < min_depth_m) continue;
    // Clip at the near plane.
    if (p.z() < min_depth_m) p = q + (p - q) * ((q.z() - min_depth_m) / (q.z() - p.z()));
    if (q.z() < min_depth_m) q = p + (q - p) * ((p.z() - min_depth_m) / (p.z() - q.z()));
    const Eigen::Vector2d a = camera.Project(p), b = camera.Project(q);
    Projected& out = projected_[i];
    out.length = (b - a).norm();
    if (!(out.length > 1e-6) || !std::isfinite(out.length)) continue;
    out.visible = true;
    out.a = a;
    out.dir = (b - a) / out.length;
    out.normal = Eigen::Vector2d(-out.dir.y(), out.dir.x());
  }
}

void ProjectedGroundTruth::LinesUnder(const Segment2d& segment, std::vector<int>* lines) const {
  lines->clear();
  const Eigen::Vector2d s = segment.head<2>(), e = segment.tail<2>();
  const double length = (e - s).norm();
  if (length < 1e-9) return;
  const Eigen::Vector2d d = (e - s) / length;
  for (size_t i = 0; i < projected_.size(); ++i) {
    const Projected& p = projected_[i];
    if (!p.visible || std::abs(d.dot(p.dir)) < cos_max_) continue;
    if (std::abs(p.normal.dot(s - p.a)) > criteria_.max_distance_px ||
        std::abs(p.normal.dot(e - p.a)) > criteria_.max_distance_px) {
      continue;
    }
    const double t0 = p.dir.dot(s - p.a), t1 = p.dir.dot(e - p.a);
    if (std::max(t0, t1) < 0.0 || std::min(t0, t1) > p.length) continue;
    lines->push_back(static_cast<int>(i));
  }
}

Eigen::Vector2d ProjectedGroundTruth::EndpointDistances(const Segment2d& segment, int index) const {
  const Projected& p = projected_.at(index);
  return {std::abs(p.normal.dot(segment.head<2>() - p.a)), std::abs(p.normal.dot(segment.tail<2>() - p.a))};
}

ProjectedGroundTruth ProjectedGroundTruthAt(const SimulatedSequence& sequence, int frame, int camera,
                                            const AuditCriteria& criteria) {
  ProjectedGroundTruth projected(sequence.lines, criteria);
  const Rigid3d left_from_world = sequence.ground_truth.at(frame).world_from_cam.Inverse();
  if (camera == 0) {
    projected.Project(left_from_world, sequence.true_rig.left);
  } else {
    projected.Project(sequence.true_rig.right_from_left * left_from_world, sequence.true_rig.right);
  }
  return projected;
}

namespace {
const nlohmann::json kVisibleTruth = {{"clip_to_image", true}, {"occlusion", true}};
}  // namespace

nlohmann::json RenderedRoomConfig(int frames, bool euroc_size) {
  nlohmann::json config = {{"frames", frames},
                           {"scene", {{"type", "room"}}},
                           {"motion", {{"type", "loop"}}},
                           {"noise", {{"endpoint_px", 0.0}}},
                           {"observation", kVisibleTruth}};
  if (euroc_size) {
    const nlohmann::json camera = {{"fx", 458.654}, {"fy", 458.654}, {"cx", 367.215}, {"cy", 248.375}};
    config["rig"] = {{"width", 752},
                     {"height", 480},
                     {"left", camera},
                     {"right", camera},
                     {"right_from_left", {{"R", {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}, {"t", {-0.11, 0, 0}}}}};
  }
  return config;
}

nlohmann::json RenderedCorridorConfig(int frames) {
  return {{"frames", frames},
          {"scene", {{"type", "corridor"}}},
          {"motion", {{"type", "forward"}, {"forward", {{"step_m", 0.01}}}}},
          {"noise", {{"endpoint_px", 0.0}}},
          {"observation", kVisibleTruth}};
}

nlohmann::json RenderedPaperConfig(int frames) {
  return {{"frames", frames},
          {"scene", {{"type", "paper"}}},
          {"motion", {{"type", "paper"}, {"sinusoid", {{"max_rotation_deg", 1.0}, {"max_translation_m", 0.01}}}}},
          {"noise", {{"endpoint_px", 0.0}}},
          {"observation", kVisibleTruth}};
}

nlohmann::json PaperSceneOptions(const StereoRig& rig) {
  const double fx_baseline = rig.left.fx * rig.right_from_left.translation.norm();
  return {{"matching",
           {{"min_disparity_px", std::floor(fx_baseline / 1.0)},
            {"max_disparity_px", std::ceil(fx_baseline / 0.2)},
            {"min_union_overlap", 0.5},
            {"max_previous_px", 1.0},
            {"previous_pairs", 3}}},
          {"tracking", {{"extend_max_px", 20.0}, {"snap_inlier_px", 0.3}}}};
}

std::vector<Line3d> WithBarSecondEdges(const SimulatedSequence& sequence) {
  std::vector<Line3d> lines = sequence.lines;
  const auto is_vertex = [](const Surface& s, const Eigen::Vector3d& x) {
    return std::any_of(s.vertices.begin(), s.vertices.end(), [&](const Eigen::Vector3d& v) { return v == x; });
  };
  for (const Line3d& line : sequence.lines) {
    for (const Surface& s : sequence.surfaces) {
      if (!s.two_sided || s.vertices.size() != 4 || !is_vertex(s, line.p) || !is_vertex(s, line.q)) continue;
      // The bar's other long edge: the two vertices that are not the line's, in the line's order.
      std::vector<Eigen::Vector3d> other;
      for (const Eigen::Vector3d& v : s.vertices) {
        if (v != line.p && v != line.q) other.push_back(v);
      }
      if (other.size() != 2) continue;
      if ((other[0] - line.p).norm() > (other[1] - line.p).norm()) std::swap(other[0], other[1]);
      lines.push_back({other[0], other[1]});
      break;
    }
  }
  return lines;
}

StereoSequence WithErrorReplaced(const SimulatedSequence& sequence, const std::vector<Line3d>& lines,
                                 const StereoSequence& observed, double sigma_px, std::uint64_t seed,
                                 const AuditCriteria& criteria) {
  SimulatedSequence judged;
  judged.true_rig = sequence.true_rig;
  judged.ground_truth = sequence.ground_truth;
  judged.lines = lines;
  // Per id, the lines under both of its segments in every frame so far (intersection).
  std::map<std::int64_t, std::vector<int>> under;
  std::vector<int> common, still;
  const int frames = static_cast<int>(observed.frames.size());
  for (int k = 0; k < frames; ++k) {
    const ProjectedGroundTruth left = ProjectedGroundTruthAt(judged, k, 0, criteria);
    const ProjectedGroundTruth right = ProjectedGroundTruthAt(judged, k, 1, criteria);
    const StereoFrame& frame = observed.frames[k];
    for (size_t i = 0; i < frame.left.size(); ++i) {
      JudgeStereoPair(left, right, frame.left[i].segment, frame.right[i].segment, &common);
      const auto [it, first] = under.emplace(frame.left[i].id, common);
      if (!first) {
        Intersect(it->second, common, &still);
        it->second.swap(still);
      }
    }
  }
  RandomStream stream = MakeStream(seed, "frontend_error_model");
  StereoSequence out = observed;
  for (int k = 0; k < frames; ++k) {
    const Rigid3d left_from_world = sequence.ground_truth.at(k).world_from_cam.Inverse();
    const Rigid3d cam_from_world[2] = {left_from_world, sequence.true_rig.right_from_left * left_from_world};
    const PinholeCamera* camera[2] = {&sequence.true_rig.left, &sequence.true_rig.right};
    StereoFrame& frame = out.frames[k];
    for (int c = 0; c < 2; ++c) {
      for (LineObservation& o : c == 0 ? frame.left : frame.right) {
        const std::vector<int>& on = under.at(o.id);
        if (on.empty()) continue;
        const Line3d& line = lines[on.front()];
        // The line's points in front of the camera (the audit found the line in view: one
        // endpoint at least is in front).
        Eigen::Vector3d p = cam_from_world[c] * line.p, q = cam_from_world[c] * line.q;
        constexpr double kMinDepth = 0.05;
        if (p.z() < kMinDepth) p += (kMinDepth - p.z()) / (q.z() - p.z()) * (q - p);
        if (q.z() < kMinDepth) q += (kMinDepth - q.z()) / (p.z() - q.z()) * (p - q);
        const Eigen::Vector2d a = camera[c]->Project(p), b = camera[c]->Project(q);
        const Eigen::Vector2d d = (b - a).normalized(), n(-d.y(), d.x());
        const Eigen::Vector2d noise = sigma_px * StandardNormalPair(stream);
        for (int e = 0; e < 2; ++e) {
          const Eigen::Vector2d x = o.segment.segment<2>(2 * e);
          o.segment.segment<2>(2 * e) = x - (n.dot(x - a) - noise[e]) * n;
        }
      }
    }
  }
  return out;
}

PairVerdict JudgeStereoPair(const ProjectedGroundTruth& left_truth, const ProjectedGroundTruth& right_truth,
                            const Segment2d& left, const Segment2d& right, std::vector<int>* common) {
  std::vector<int> under_left, under_right;
  left_truth.LinesUnder(left, &under_left);
  right_truth.LinesUnder(right, &under_right);
  Intersect(under_left, under_right, common);
  if (!common->empty()) return PairVerdict::kCorrect;
  return under_left.empty() && under_right.empty() ? PairVerdict::kUnjudged : PairVerdict::kWrong;
}

EdgeStep MeasureEdgeStep(const cv::Mat& noise_free_grey, const Segment2d& segment) {
  EdgeStep result;
  const Eigen::Vector2d a = segment.head<2>(), b = segment.tail<2>();
  const double length = (b - a).norm();
  if (length < 1e-9) return result;
  const Eigen::Vector2d d = (b - a) / length, n(-d.y(), d.x());
  std::vector<double> steps;
  double level = 0.0;
  for (double t = 3.0; t <= length - 3.0; t += 2.0) {
    const Eigen::Vector2d plus = a + t * d + 2.0 * n, minus = a + t * d - 2.0 * n;
    const float i_plus = SampleBilinear<uchar>(noise_free_grey, plus.x(), plus.y());
    const float i_minus = SampleBilinear<uchar>(noise_free_grey, minus.x(), minus.y());
    steps.push_back(std::abs(i_plus - i_minus));
    level += 0.5 * (i_plus + i_minus);
  }
  if (steps.empty()) return result;
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  result.step = steps[steps.size() / 2];
  result.level = level / steps.size();
  return result;
}

std::vector<LineObservation> PhotometricallyVisible(const std::vector<LineObservation>& visible,
                                                    const cv::Mat& noise_free_grey, const ImageConfig& images,
                                                    double min_noise_multiples) {
  std::vector<LineObservation> out;
  for (const LineObservation& o : visible) {
    const EdgeStep e = MeasureEdgeStep(noise_free_grey, o.segment);
    // The noise model of render/image_formation.h at the edge's grey level.
    const double sigma = std::sqrt(images.read_noise * images.read_noise + images.shot_noise * std::max(0.0, e.level));
    // A step of zero is no edge even in a noise-free image (sigma 0).
    if (e.step > 0.0 && e.step >= min_noise_multiples * std::sqrt(2.0) * sigma) out.push_back(o);
  }
  return out;
}

void ScoreDetections(const ProjectedGroundTruth& projected, const std::vector<LineObservation>& visible,
                     const std::vector<ImageLine>& detections, double min_gt_length_px, DetectionScore* score) {
  ++score->images;
  score->detections += static_cast<int>(detections.size());
  std::vector<int> under;
  std::vector<std::vector<int>> detections_on(detections.size());
  for (size_t j = 0; j < detections.size(); ++j) {
    projected.LinesUnder(detections[j].segment, &detections_on[j]);
    if (!detections_on[j].empty()) ++score->detections_on_gt;
  }
  for (const LineObservation& o : visible) {
    if ((o.segment.tail<2>() - o.segment.head<2>()).norm() < min_gt_length_px) continue;
    ++score->gt_segments;
    bool found = false;
    for (size_t j = 0; j < detections.size(); ++j) {
      const std::vector<int>& on = detections_on[j];
      if (!std::binary_search(on.begin(), on.end(), static_cast<int>(o.id))) continue;
      found = true;
      const Eigen::Vector2d d = projected.EndpointDistances(detections[j].segment, static_cast<int>(o.id));
      score->endpoint_sq_sum += d.squaredNorm();
      score->endpoints += 2;
    }
    if (found) ++score->gt_found;
  }
}

FrontEndAudit::FrontEndAudit(const SimulatedSequence& sequence, const AuditCriteria& criteria)
    : sequence_(sequence), criteria_(criteria), projected_{ProjectedGroundTruth(sequence.lines, criteria),
                                      ProjectedGroundTruth(sequence.lines, criteria)} {}

void FrontEndAudit::AddFrame(int k, const StereoFrontEnd& front_end, const StereoFrame& frame) {
  const FrontEndFrameStats& stats = front_end.last_stats();
  // The matches were made in the pair of frame k - detection_lag.
  const int matched_frame = stats.detected ? k - stats.detection_lag : k;
  for (int c = 0; c < 2; ++c) projected_[c] = ProjectedGroundTruthAt(sequence_, matched_frame, c, criteria_);
  if (stats.detected) {
    for (const StereoMatch& m : front_end.last_matches()) {
      const PairVerdict verdict = JudgeStereoPair(projected_[0], projected_[1], front_end.last_detections(0)[m.left].segment,
                                                  front_end.last_detections(1)[m.right].segment, &common_);
      ++result_.matches;
      if (verdict == PairVerdict::kCorrect) ++result_.matches_correct;
      if (verdict == PairVerdict::kUnjudged) ++result_.matches_unjudged;
    }
  }
  if (matched_frame != k) {
    for (int c = 0; c < 2; ++c) projected_[c] = ProjectedGroundTruthAt(sequence_, k, c, criteria_);
  }
  // Tracks: the lines of the output frame (left and right hold the same ids in the same order).
  for (auto& [id, track] : tracks_) track.seen = false;
  for (size_t i = 0; i < frame.left.size(); ++i) {
    const std::int64_t id = frame.left[i].id;
    JudgeStereoPair(projected_[0], projected_[1], frame.left[i].segment, frame.right[i].segment, &common_);
    auto it = tracks_.find(id);
    if (it == tracks_.end()) {
      it = tracks_.emplace(id, Track{common_, 0, false, !common_.empty()}).first;
      ++result_.added;
      if (!common_.empty()) ++result_.added_correct;
    } else {
      std::vector<int> still;
      Intersect(it->second.lines, common_, &still);
      it->second.lines.swap(still);
    }
    it->second.seen = true;
    ++it->second.frames;
    if (!common_.empty()) {
      const int line = common_.front();
      result_.endpoint_sq_sum += projected_[0].EndpointDistances(frame.left[i].segment, line).squaredNorm() +
                                 projected_[1].EndpointDistances(frame.right[i].segment, line).squaredNorm();
      result_.endpoints += 4;
    }
  }
  std::vector<std::int64_t> ended;
  for (const auto& [id, track] : tracks_) {
    if (!track.seen) ended.push_back(id);
  }
  for (std::int64_t id : ended) CloseTrack(id);
}

void FrontEndAudit::CloseTrack(std::int64_t id) {
  const auto it = tracks_.find(id);
  if (it == tracks_.end()) return;
  if (it->second.frames >= 2) {
    if (!it->second.judged) {
      ++result_.tracks_unjudged;
    } else {
      ++result_.tracks;
      result_.track_frames += it->second.frames;
      result_.longest_track = std::max(result_.longest_track, it->second.frames);
      if (!it->second.lines.empty()) ++result_.tracks_correct;
    }
  }
  tracks_.erase(it);
}

void FrontEndAudit::Finish() {
  while (!tracks_.empty()) CloseTrack(tracks_.begin()->first);
}

}  // namespace slt
