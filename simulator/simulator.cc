#include "simulator/simulator.h"

#include <optional>
#include <utility>

#include "simulator/clipping.h"
#include "simulator/motion.h"
#include "simulator/random_draws.h"

namespace slt {
namespace {

// Everything one camera needs to observe the scene in one frame.
struct ObservationContext {
  const SimulationConfig* config;
  const std::vector<Line3d>* lines;
  const KeyedStream* noise;
  const KeyedStream* outliers;
  const Occluders* occluders;  // null: every part of a line in view is seen
  int width;
  int height;
};

// A random segment in the image at least min_length_px long: the outlier model. Rejection
// terminates quickly: Check() keeps min_length_px at most half the smaller image side.
Segment2d RandomSegment(SplitMix64& g, int width, int height, double min_length_px) {
  while (true) {
    const Segment2d s(Uniform(g, 0.0, width - 1.0), Uniform(g, 0.0, height - 1.0), Uniform(g, 0.0, width - 1.0),
                      Uniform(g, 0.0, height - 1.0));
    if ((s.head<2>() - s.tail<2>()).norm() >= min_length_px) return s;
  }
}

// The noise-free image of the 3-D segment p-q (camera coordinates) under the observation
// model: cut at the near plane, projected, clipped to the image when clipping. False when
// nothing of it is seen or it is shorter than min_length_px.
bool NoiseFreeImage(const ObservationContext& ctx, const PinholeCamera& camera, Eigen::Vector3d p, Eigen::Vector3d q,
                    Eigen::Vector2d* a, Eigen::Vector2d* b) {
  const ObservationConfig& obs = ctx.config->observation;
  if (obs.clip_to_image) {
    if (!ClipSegmentToDepth(obs.min_depth_m, &p, &q)) return false;
    *a = camera.Project(p);
    *b = camera.Project(q);
    return ClipSegmentToImage(ctx.width, ctx.height, a, b) && (*a - *b).norm() >= obs.min_length_px;
  }
  if (p.z() < obs.min_depth_m || q.z() < obs.min_depth_m) return false;
  *a = camera.Project(p);
  *b = camera.Project(q);
  return (*a - *b).norm() >= obs.min_length_px;
}

void Observe(const ObservationContext& ctx, const Rigid3d& cam_from_world, const PinholeCamera& camera,
             std::uint64_t frame, std::uint64_t camera_index, std::vector<LineObservation>* out) {
  const SimulationConfig& config = *ctx.config;
  const ObservationConfig& obs = config.observation;
  const NoiseConfig& noise = config.noise;
  const KeyedStream::ImageKey noise_draws = ctx.noise->Image(frame, camera_index);
  const KeyedStream::ImageKey outlier_draws = ctx.outliers->Image(frame, camera_index);
  const Eigen::Vector3d eye = cam_from_world.Center();
  std::vector<Eigen::Vector2d> visible;  // visible parts of one line, reused
  out->reserve(ctx.lines->size());
  for (std::size_t id = 0; id < ctx.lines->size(); ++id) {
    const Line3d& line = (*ctx.lines)[id];
    Eigen::Vector3d p = cam_from_world * line.p, q = cam_from_world * line.q;

    // The noise variates come first in the observation's stream, at unit scale, so that they
    // are the same for every noise level and endpoint model.
    SplitMix64 g = noise_draws.At(id);
    Eigen::Vector4d offset;
    if (noise.model == NoiseModel::kUniform) {
      for (int i = 0; i < 4; ++i) offset[i] = Uniform(g, -1.0, 1.0);
    } else {
      offset << StandardNormalPair(g), StandardNormalPair(g);
    }
    offset *= noise.endpoint_px;
    double s0 = 0.0, s1 = 1.0;
    if (noise.endpoints == EndpointModel::kSliding) {
      s0 = Uniform(g, 0.0, noise.slide_fraction);
      s1 = Uniform(g, 1.0 - noise.slide_fraction, 1.0);
      const Eigen::Vector3d d = q - p;
      q = p + s1 * d;
      p = p + s0 * d;
    }

    // Whether a line is seen is decided on its noise-free image, so that every noise level of
    // a sweep observes the same lines. With occlusion, of the visible parts of the (slid)
    // segment the one with the longest image is observed: a line split by an occluder is
    // seen as one of its pieces, as a detector that does not join collinear segments sees it.
    Eigen::Vector2d a, b;
    if (ctx.occluders == nullptr) {
      if (!NoiseFreeImage(ctx, camera, p, q, &a, &b)) continue;
    } else {
      // Occlusion only matters for a line in view (most of a room is not).
      if (!NoiseFreeImage(ctx, camera, p, q, &a, &b)) continue;
      ctx.occluders->VisibleParts(eye, line.p, line.q, &visible);
      const Eigen::Vector3d d = cam_from_world * line.q - cam_from_world * line.p;
      const Eigen::Vector3d base = cam_from_world * line.p;
      double best = -1.0;
      for (const Eigen::Vector2d& part : visible) {
        const double lo = std::max(part[0], s0), hi = std::min(part[1], s1);
        Eigen::Vector2d pa, pb;
        if (lo >= hi || !NoiseFreeImage(ctx, camera, base + lo * d, base + hi * d, &pa, &pb)) continue;
        if ((pa - pb).norm() > best) {
          best = (pa - pb).norm();
          a = pa;
          b = pb;
        }
      }
      if (best < 0.0) continue;
    }
    a += offset.head<2>();
    b += offset.tail<2>();
    // With clipping the noisy endpoints are clipped again: a detector reports points inside.
    // Only a segment running along the border can be pushed out entirely; it is dropped.
    if (obs.clip_to_image && !ClipSegmentToImage(ctx.width, ctx.height, &a, &b)) continue;

    LineObservation observation;
    observation.id = static_cast<std::int64_t>(id);
    observation.segment << a, b;
    // The rate test only saves the draw when there are no outliers (it would never pass).
    if (config.outliers.rate > 0.0) {
      SplitMix64 o = outlier_draws.At(id);
      if (Uniform01(o) < config.outliers.rate) {
        observation.segment = RandomSegment(o, ctx.width, ctx.height, obs.min_length_px);
      }
    }
    out->push_back(observation);
  }
}

}  // namespace

SimulatedSequence Simulate(const SimulationConfig& config) {
  config.Check();
  SimulatedSequence result;
  result.true_rig = config.rig;
  result.sequence.rig = config.TrackerRig();
  Scene scene = MakeScene(config.scene, config.SceneSeed());
  result.lines = std::move(scene.lines);
  result.surfaces = std::move(scene.surfaces);
  if (config.max_features > 0 && result.lines.size() > static_cast<std::size_t>(config.max_features)) {
    result.lines.resize(static_cast<std::size_t>(config.max_features));
  }
  result.ground_truth = MakeTrajectory(config.motion, config.frames, config.frame_rate, config.MotionSeed());

  const KeyedStream noise(config.NoiseSeed(), "noise"), outliers(config.OutlierSeed(), "outliers");
  const StereoRig& rig = config.rig;
  std::optional<Occluders> occluders;
  if (config.observation.occlusion) occluders.emplace(result.surfaces);
  const ObservationContext ctx{&config,      &result.lines, &noise, &outliers, occluders ? &*occluders : nullptr,
                               rig.width, rig.height};
  result.sequence.frames.resize(result.ground_truth.size());
  for (std::size_t k = 0; k < result.ground_truth.size(); ++k) {
    StereoFrame& frame = result.sequence.frames[k];
    frame.time = result.ground_truth[k].time;
    const Rigid3d left_from_world = result.ground_truth[k].world_from_cam.Inverse();
    Observe(ctx, left_from_world, rig.left, k, 0, &frame.left);
    Observe(ctx, rig.right_from_left * left_from_world, rig.right, k, 1, &frame.right);
  }
  return result;
}

}  // namespace slt
