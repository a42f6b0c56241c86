#include "evaluation/metrics.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/json_reader.h"
#include "geometry/se3.h"

namespace slt {
namespace {

constexpr double kDegreesPerRadian = 180.0 / M_PI;
constexpr size_t kUnpaired = static_cast<size_t>(-1);

std::string Number(double value) { return nlohmann::json(value).dump(); }

void CheckTimesNonDecreasing(const Trajectory& trajectory, const std::string& name) {
  for (size_t k = 1; k < trajectory.size(); ++k) {
    if (trajectory[k].time < trajectory[k - 1].time) {
      throw std::invalid_argument(name + ": pose " + std::to_string(k) + " (time " + Number(trajectory[k].time) +
                                  ") is before the previous pose (time " + Number(trajectory[k - 1].time) + ")");
    }
  }
}

FrameError PoseError(int frame, double time, const Rigid3d& gt, const Rigid3d& est) {
  return {frame, time, (est.translation - gt.translation).norm(),
          RotationAngle(gt.rotation.transpose() * est.rotation) * kDegreesPerRadian};
}

std::string TimeRange(const Trajectory& trajectory) {
  return trajectory.empty() ? std::string("no poses")
                            : "times " + Number(trajectory.front().time) + " to " + Number(trajectory.back().time);
}

}  // namespace

namespace {

// AssociateByTime; std::invalid_argument when nothing associates.
std::vector<PosePair> AssociateOrThrow(const Trajectory& gt, const Trajectory& est, double max_time_diff_s) {
  std::vector<PosePair> pairs = AssociateByTime(gt, est, max_time_diff_s);
  if (pairs.empty()) {
    throw std::invalid_argument("no estimate pose is within " + Number(max_time_diff_s) +
                                " s of a ground-truth pose (ground truth: " + TimeRange(gt) +
                                "; estimate: " + TimeRange(est) + ")");
  }
  return pairs;
}

}  // namespace

const char* AlignmentName(Alignment alignment) {
  switch (alignment) {
    case Alignment::kNone: return "none";
    case Alignment::kSE3: return "se3";
    case Alignment::kSim3: return "sim3";
  }
  return "unknown";
}

Alignment AlignmentFromName(const std::string& name) {
  for (Alignment a : {Alignment::kNone, Alignment::kSE3, Alignment::kSim3}) {
    if (name == AlignmentName(a)) return a;
  }
  throw std::invalid_argument("unknown alignment '" + name + "' (expected none, se3 or sim3)");
}

void EvaluationOptions::Check(const std::string& where) const {
  if (!(max_time_diff_s >= 0.0) || !std::isfinite(max_time_diff_s)) {
    ThrowOptionError(where, "", "max_time_diff_s", "must be a finite number >= 0");
  }
  if (rpe_delta_frames < 1) ThrowOptionError(where, "", "rpe_delta_frames", "must be >= 1");
}

std::vector<PosePair> AssociateByTime(const Trajectory& gt, const Trajectory& est, double max_time_diff_s) {
  CheckTimesNonDecreasing(gt, "ground truth");
  CheckTimesNonDecreasing(est, "estimate");
  // owner[j]: the estimate pose that holds ground-truth pose j, and its time difference.
  std::vector<size_t> owner(gt.size(), kUnpaired);
  std::vector<double> owner_diff(gt.size(), 0.0);
  for (size_t i = 0; i < est.size(); ++i) {
    const double t = est[i].time;
    const auto after = std::lower_bound(gt.begin(), gt.end(), t,
                                        [](const TimedPose& pose, double time) { return pose.time < time; });
    // The nearest is the first pose at or after t or the one before it; ties go to the earlier.
    size_t j = static_cast<size_t>(after - gt.begin());
    if (after == gt.end() || (after != gt.begin() && t - (after - 1)->time <= after->time - t)) --j;
    if (j >= gt.size()) continue;  // empty ground truth
    const double diff = std::abs(gt[j].time - t);
    if (diff > max_time_diff_s) continue;
    if (owner[j] == kUnpaired || diff < owner_diff[j]) {
      owner[j] = i;
      owner_diff[j] = diff;
    }
  }
  std::vector<PosePair> pairs;
  for (size_t j = 0; j < gt.size(); ++j) {
    if (owner[j] != kUnpaired) pairs.push_back({j, owner[j]});
  }
  std::sort(pairs.begin(), pairs.end(), [](const PosePair& a, const PosePair& b) { return a.est_index < b.est_index; });
  return pairs;
}

SimilarityTransform UmeyamaAlignment(const std::vector<Eigen::Vector3d>& source,
                                     const std::vector<Eigen::Vector3d>& target, bool with_scale) {
  if (source.size() != target.size()) {
    throw std::invalid_argument("alignment: " + std::to_string(source.size()) + " source points but " +
                                std::to_string(target.size()) + " target points");
  }
  const size_t n = source.size();
  if (n < 3) throw std::invalid_argument("alignment: needs at least 3 poses, got " + std::to_string(n));
  Eigen::Vector3d source_mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d target_mean = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    source_mean += source[i];
    target_mean += target[i];
  }
  source_mean /= static_cast<double>(n);
  target_mean /= static_cast<double>(n);
  // Umeyama eq. 36 and 38: the variance of the source and the target-source covariance.
  double source_variance = 0.0;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d s = source[i] - source_mean;
    covariance += (target[i] - target_mean) * s.transpose();
    source_variance += s.squaredNorm();
  }
  covariance /= static_cast<double>(n);
  source_variance /= static_cast<double>(n);

  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d& d = svd.singularValues();  // descending
  // The rotation is unique only when the covariance has rank >= 2, i.e. the points are
  // neither coincident nor collinear (evo refuses the same configurations).
  if (!(d(1) > 1e-12 * d(0))) {
    throw std::invalid_argument("alignment: the positions are coincident or collinear; the alignment is undetermined");
  }
  // Eq. 39-43: the sign correction keeps R a rotation (det +1) rather than a reflection.
  Eigen::Vector3d s(1.0, 1.0, 1.0);
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) s(2) = -1.0;
  SimilarityTransform transform;
  transform.rotation = svd.matrixU() * s.asDiagonal() * svd.matrixV().transpose();
  transform.scale = with_scale ? d.dot(s) / source_variance : 1.0;
  transform.translation = target_mean - transform.scale * (transform.rotation * source_mean);
  return transform;
}

TrajectoryErrors EvaluateTrajectory(const Trajectory& gt, const Trajectory& est, const EvaluationOptions& options) {
  options.Check();
  TrajectoryErrors errors;
  errors.options = options;
  errors.gt_poses = gt.size();
  errors.est_poses = est.size();

  const std::vector<PosePair> pairs = AssociateOrThrow(gt, est, options.max_time_diff_s);
  const size_t n = pairs.size();
  errors.associated_poses = n;
  if (n < static_cast<size_t>(options.rpe_delta_frames) + 1) {
    throw std::invalid_argument("only " + std::to_string(n) + " poses associate; RPE with delta " +
                                std::to_string(options.rpe_delta_frames) + " needs at least " +
                                std::to_string(options.rpe_delta_frames + 1));
  }

  std::vector<Rigid3d> gt_poses, est_poses;
  gt_poses.reserve(n);
  est_poses.reserve(n);
  for (const PosePair& p : pairs) {
    gt_poses.push_back(gt[p.gt_index].world_from_cam);
    est_poses.push_back(est[p.est_index].world_from_cam);
  }
  if (options.alignment != Alignment::kNone) {
    std::vector<Eigen::Vector3d> est_positions, gt_positions;
    for (size_t k = 0; k < n; ++k) {
      est_positions.push_back(est_poses[k].translation);
      gt_positions.push_back(gt_poses[k].translation);
    }
    errors.alignment = UmeyamaAlignment(est_positions, gt_positions, options.alignment == Alignment::kSim3);
    for (Rigid3d& pose : est_poses) pose = errors.alignment.Apply(pose);
  }

  std::vector<double> ate_trans, ate_rot;
  for (size_t k = 0; k < n; ++k) {
    const size_t j = pairs[k].gt_index;
    errors.per_frame.push_back(PoseError(static_cast<int>(j), gt[j].time, gt_poses[k], est_poses[k]));
    ate_trans.push_back(errors.per_frame.back().trans_err_m);
    ate_rot.push_back(errors.per_frame.back().rot_err_deg);
  }
  errors.ate_trans_m = ComputeStatistics(std::move(ate_trans));
  errors.ate_rot_deg = ComputeStatistics(std::move(ate_rot));

  // evo's pairs: consecutive (i, i + delta) with i = 0, delta, 2 delta, ... or, with all_pairs,
  // every i. E compares the estimated motion over the pair with the true one.
  const size_t delta = static_cast<size_t>(options.rpe_delta_frames);
  const size_t step = options.rpe_all_pairs ? 1 : delta;
  std::vector<double> rpe_trans, rpe_rot;
  for (size_t i = 0; i + delta < n; i += step) {
    const Rigid3d gt_motion = gt_poses[i].Inverse() * gt_poses[i + delta];
    const Rigid3d est_motion = est_poses[i].Inverse() * est_poses[i + delta];
    const Rigid3d e = gt_motion.Inverse() * est_motion;
    rpe_trans.push_back(e.translation.norm());
    rpe_rot.push_back(RotationAngle(e.rotation) * kDegreesPerRadian);
  }
  errors.rpe_trans_m = ComputeStatistics(std::move(rpe_trans));
  errors.rpe_rot_deg = ComputeStatistics(std::move(rpe_rot));
  return errors;
}

void KittiOdometryOptions::Check(const std::string& where) const {
  if (segment_lengths_m.empty()) throw ConfigError(where + ": key 'segment_lengths_m': needs at least one length");
  for (const double length : segment_lengths_m) {
    if (!(length > 0.0) || !std::isfinite(length)) {
      throw ConfigError(where + ": key 'segment_lengths_m': lengths must be finite and > 0, got " + Number(length));
    }
  }
  if (step_frames < 1) throw ConfigError(where + ": key 'step_frames': must be >= 1");
  if (!(max_time_diff_s >= 0.0) || !std::isfinite(max_time_diff_s)) {
    throw ConfigError(where + ": key 'max_time_diff_s': must be a finite number >= 0");
  }
}

KittiOdometryErrors EvaluateKittiOdometry(const Trajectory& gt, const Trajectory& est,
                                          const KittiOdometryOptions& options) {
  options.Check();
  const std::vector<PosePair> pairs = AssociateOrThrow(gt, est, options.max_time_diff_s);
  const size_t n = pairs.size();
  std::vector<double> distance(n, 0.0);
  for (size_t k = 1; k < n; ++k) {
    distance[k] = distance[k - 1] + (gt[pairs[k].gt_index].world_from_cam.translation -
                                     gt[pairs[k - 1].gt_index].world_from_cam.translation).norm();
  }
  KittiOdometryErrors errors;
  errors.options = options;
  errors.path_length_m = distance.back();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double trans_sum = 0.0, rot_sum = 0.0;
  for (const double length : options.segment_lengths_m) {
    KittiSegmentErrors per_length;
    per_length.length_m = length;
    double trans = 0.0, rot = 0.0;
    for (size_t i = 0; i < n; i += static_cast<size_t>(options.step_frames)) {
      // The devkit's lastFrameFromSegmentLength.
      size_t j = i;
      while (j < n && !(distance[j] > distance[i] + length)) ++j;
      if (j == n) continue;
      const Rigid3d& gt_i = gt[pairs[i].gt_index].world_from_cam;
      const Rigid3d& gt_j = gt[pairs[j].gt_index].world_from_cam;
      const Rigid3d& est_i = est[pairs[i].est_index].world_from_cam;
      const Rigid3d& est_j = est[pairs[j].est_index].world_from_cam;
      const Rigid3d e = (est_i.Inverse() * est_j).Inverse() * (gt_i.Inverse() * gt_j);
      trans += e.translation.norm() / length;
      rot += RotationAngle(e.rotation) * kDegreesPerRadian / length;
      ++per_length.segments;
    }
    per_length.trans_err_pct = per_length.segments > 0 ? 100.0 * trans / per_length.segments : nan;
    per_length.rot_err_deg_per_m = per_length.segments > 0 ? rot / per_length.segments : nan;
    errors.segments += per_length.segments;
    trans_sum += trans;
    rot_sum += rot;
    errors.per_length.push_back(per_length);
  }
  errors.trans_err_pct = errors.segments > 0 ? 100.0 * trans_sum / errors.segments : nan;
  errors.rot_err_deg_per_m = errors.segments > 0 ? rot_sum / errors.segments : nan;
  return errors;
}

nlohmann::json ToJson(const KittiOdometryErrors& errors) {
  const auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  nlohmann::json per_length = nlohmann::json::array();
  for (const KittiSegmentErrors& s : errors.per_length) {
    per_length.push_back({{"length_m", s.length_m},
                          {"segments", s.segments},
                          {"trans_err_pct", number(s.trans_err_pct)},
                          {"rot_err_deg_per_m", number(s.rot_err_deg_per_m)}});
  }
  return {{"path_length_m", errors.path_length_m},
          {"step_frames", errors.options.step_frames},
          {"segments", errors.segments},
          {"trans_err_pct", number(errors.trans_err_pct)},
          {"rot_err_deg_per_m", number(errors.rot_err_deg_per_m)},
          {"per_length", per_length}};
}

nlohmann::json ToJson(const ErrorStatistics& s) {
  return {{"count", s.count}, {"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median},
          {"std", s.std},     {"min", s.min},   {"max", s.max}};
}

nlohmann::json ToJson(const ErrorCurve& curve) {
  nlohmann::json frame = nlohmann::json::array(), time = nlohmann::json::array(),
                 trans = nlohmann::json::array(), rot = nlohmann::json::array();
  for (const FrameError& e : curve) {
    frame.push_back(e.frame);
    time.push_back(e.time_s);
    trans.push_back(e.trans_err_m);
    rot.push_back(e.rot_err_deg);
  }
  return {{"frame", frame}, {"time_s", time}, {"trans_err_m", trans}, {"rot_err_deg", rot}};
}

nlohmann::json ToJson(const TrajectoryErrors& errors, bool include_per_frame) {
  const SimilarityTransform& a = errors.alignment;
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) rows.push_back({a.rotation(i, 0), a.rotation(i, 1), a.rotation(i, 2)});
  const FrameError& final_error = errors.Final();
  nlohmann::json j = {
      {"alignment", AlignmentName(errors.options.alignment)},
      {"max_time_diff_s", errors.options.max_time_diff_s},
      {"rpe_delta_frames", errors.options.rpe_delta_frames},
      {"rpe_all_pairs", errors.options.rpe_all_pairs},
      {"gt_poses", errors.gt_poses},
      {"est_poses", errors.est_poses},
      {"associated_poses", errors.associated_poses},
      {"gt_world_from_est_world",
       {{"R", rows}, {"t", {a.translation.x(), a.translation.y(), a.translation.z()}}, {"scale", a.scale}}},
      {"ate_trans_m", ToJson(errors.ate_trans_m)},
      {"ate_rot_deg", ToJson(errors.ate_rot_deg)},
      {"rpe_trans_m", ToJson(errors.rpe_trans_m)},
      {"rpe_rot_deg", ToJson(errors.rpe_rot_deg)},
      {"final_frame", final_error.frame},
      {"final_time_s", final_error.time_s},
      {"final_trans_err_m", final_error.trans_err_m},
      {"final_rot_err_deg", final_error.rot_err_deg},
  };
  if (include_per_frame) j["per_frame"] = ToJson(errors.per_frame);
  return j;
}

ErrorCurve MeanErrorCurve(const std::vector<ErrorCurve>& trials) {
  if (trials.empty()) throw std::invalid_argument("mean error curve: no trials");
  ErrorCurve mean(trials.front().size());
  for (size_t t = 0; t < trials.size(); ++t) {
    const ErrorCurve& curve = trials[t];
    if (curve.size() != mean.size()) {
      throw std::invalid_argument("mean error curve: trial " + std::to_string(t) + " has " +
                                  std::to_string(curve.size()) + " frames, trial 0 has " +
                                  std::to_string(mean.size()));
    }
    for (size_t k = 0; k < curve.size(); ++k) {
      if (curve[k].frame != trials.front()[k].frame) {
        throw std::invalid_argument("mean error curve: entry " + std::to_string(k) + " is frame " +
                                    std::to_string(curve[k].frame) + " in trial " + std::to_string(t) +
                                    " but frame " + std::to_string(trials.front()[k].frame) + " in trial 0");
      }
      mean[k].frame = curve[k].frame;
      mean[k].time_s += curve[k].time_s;
      mean[k].trans_err_m += curve[k].trans_err_m;
      mean[k].rot_err_deg += curve[k].rot_err_deg;
    }
  }
  const double count = static_cast<double>(trials.size());
  for (FrameError& e : mean) {
    e.time_s /= count;
    e.trans_err_m /= count;
    e.rot_err_deg /= count;
  }
  return mean;
}

const FrameError& ErrorAtFrame(const ErrorCurve& curve, int frame) {
  const auto it = std::find_if(curve.begin(), curve.end(), [frame](const FrameError& e) { return e.frame == frame; });
  if (it == curve.end()) throw std::out_of_range("error curve has no frame " + std::to_string(frame));
  return *it;
}

}  // namespace slt
