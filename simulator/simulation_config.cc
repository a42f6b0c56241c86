#include "simulator/simulation_config.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "common/json_reader.h"
#include "dataset/stereo_lines_io.h"

namespace slt {
namespace {

constexpr std::array<std::pair<SceneType, const char*>, 3> kSceneTypes{{
    {SceneType::kPaper, "paper"}, {SceneType::kRoom, "room"}, {SceneType::kCorridor, "corridor"}}};
constexpr std::array<std::pair<MotionType, const char*>, 5> kMotionTypes{{{MotionType::kPaper, "paper"},
                                                                          {MotionType::kLoop, "loop"},
                                                                          {MotionType::kForward, "forward"},
                                                                          {MotionType::kStatic, "static"},
                                                                          {MotionType::kPureRotation, "pure_rotation"}}};
constexpr std::array<std::pair<NoiseModel, const char*>, 2> kNoiseModels{{
    {NoiseModel::kUniform, "uniform"}, {NoiseModel::kGaussian, "gaussian"}}};
constexpr std::array<std::pair<EndpointModel, const char*>, 2> kEndpointModels{{
    {EndpointModel::kFixed, "fixed"}, {EndpointModel::kSliding, "sliding"}}};

template <typename Enum, std::size_t N>
const char* NameOf(const std::array<std::pair<Enum, const char*>, N>& table, Enum value) {
  for (const auto& [e, name] : table) {
    if (e == value) return name;
  }
  return "unknown";
}

template <typename Enum, std::size_t N>
void GetEnum(JsonReader& r, const std::string& key, const std::array<std::pair<Enum, const char*>, N>& table,
             Enum* value) {
  std::string name = NameOf(table, *value);
  r.Get(key, &name);
  std::string known;
  for (const auto& [e, n] : table) {
    if (name == n) {
      *value = e;
      return;
    }
    known += std::string(known.empty() ? "" : ", ") + "\"" + n + "\"";
  }
  r.Fail(key, "unknown value \"" + name + "\" (expected one of " + known + ")");
}

// null or absent: no override.
void GetSeedOverride(JsonReader& r, const std::string& key, std::optional<std::uint64_t>* value) {
  const nlohmann::json* v = r.Find(key);
  if (v == nullptr || v->is_null()) return;
  std::uint64_t seed = 0;
  r.Get(key, &seed);
  *value = seed;
}

void GetVector3(JsonReader& r, const std::string& key, Eigen::Vector3d* value) {
  const nlohmann::json* v = r.Find(key);
  if (v == nullptr) return;
  if (!v->is_array() || v->size() != 3 || !(*v)[0].is_number() || !(*v)[1].is_number() ||
      !(*v)[2].is_number()) {
    r.Fail(key, "expected an array of 3 numbers");
  }
  *value = {(*v)[0].get<double>(), (*v)[1].get<double>(), (*v)[2].get<double>()};
}

nlohmann::json Vector3ToJson(const Eigen::Vector3d& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

nlohmann::json SeedToJson(const std::optional<std::uint64_t>& seed) {
  return seed ? nlohmann::json(*seed) : nlohmann::json(nullptr);
}

}  // namespace

const char* SceneTypeName(SceneType type) { return NameOf(kSceneTypes, type); }
const char* MotionTypeName(MotionType type) { return NameOf(kMotionTypes, type); }
const char* NoiseModelName(NoiseModel model) { return NameOf(kNoiseModels, model); }
const char* EndpointModelName(EndpointModel model) { return NameOf(kEndpointModels, model); }

MotionType DefaultMotionFor(SceneType type) {
  switch (type) {
    case SceneType::kPaper: return MotionType::kPaper;
    case SceneType::kRoom: return MotionType::kLoop;
    case SceneType::kCorridor: return MotionType::kForward;
  }
  return MotionType::kPaper;
}

StereoRig SimulationConfig::TrackerRig() const {
  StereoRig tracker_rig = rig;
  for (PinholeCamera* camera : {&tracker_rig.left, &tracker_rig.right}) {
    camera->fx += focal_error_px;
    camera->fy += focal_error_px;
  }
  return tracker_rig;
}

void SimulationConfig::Check(const std::string& where) const {
  const auto fail = [&](const std::string& key, const std::string& reason) {
    throw ConfigError(where + ": key '" + key + "': " + reason);
  };
  // Written as !(x >= lo) so that NaN fails too.
  const auto at_least = [&](double value, double lo, const std::string& key) {
    if (!(value >= lo) || !std::isfinite(value)) fail(key, "must be a finite number >= " + nlohmann::json(lo).dump());
  };
  const auto positive = [&](double value, const std::string& key) {
    if (!(value > 0.0) || !std::isfinite(value)) fail(key, "must be a finite number > 0");
  };

  if (frames < 1) fail("frames", "must be >= 1");
  if (motion.type == MotionType::kLoop && frames < 2) fail("frames", "a loop needs at least 2 frames");
  positive(frame_rate, "frame_rate");
  try {
    rig.Check();
  } catch (const std::invalid_argument& e) {
    fail("rig", e.what());
  }
  if (!std::isfinite(focal_error_px)) fail("focal_error_px", "must be finite");
  for (const PinholeCamera* camera : {&rig.left, &rig.right}) {
    if (std::min(camera->fx, camera->fy) + focal_error_px <= 0.0) {
      fail("focal_error_px", "makes a focal length of the tracker's rig non-positive");
    }
  }
  if (max_features < 0) fail("max_features", "must be >= 0 (0 = all lines)");

  const PaperSceneConfig& paper = scene.paper;
  if (paper.lines < 1) fail("scene.paper.lines", "must be >= 1");
  positive(paper.min_length_m, "scene.paper.min_length_m");
  if (!(paper.max_length_m >= paper.min_length_m) || !std::isfinite(paper.max_length_m)) {
    fail("scene.paper.max_length_m", "must be finite and >= scene.paper.min_length_m");
  }
  if (!paper.box_center_m.allFinite()) fail("scene.paper.box_center_m", "must be finite");
  if (!paper.box_size_m.allFinite() || (paper.box_size_m.array() < 0.0).any()) {
    fail("scene.paper.box_size_m", "must be finite and >= 0");
  }
  if (!(paper.cuboid_fraction >= 0.0 && paper.cuboid_fraction <= 1.0)) {
    fail("scene.paper.cuboid_fraction", "must be in [0, 1]");
  }
  // The furniture has fixed sizes (a 2 m bookshelf, 2.05 m doors): smaller rooms cannot hold it.
  const RoomSceneConfig& room = scene.room;
  at_least(room.width_m, 4.6, "scene.room.width_m");
  at_least(room.depth_m, 4.0, "scene.room.depth_m");
  at_least(room.height_m, 2.3, "scene.room.height_m");
  if (!(room.camera_height_m > 0.0 && room.camera_height_m < room.height_m)) {
    fail("scene.room.camera_height_m", "must be between the floor and the ceiling");
  }
  const CorridorSceneConfig& corridor = scene.corridor;
  at_least(corridor.width_m, 1.2, "scene.corridor.width_m");
  at_least(corridor.height_m, 2.3, "scene.corridor.height_m");
  at_least(corridor.length_m, 6.0, "scene.corridor.length_m");
  if (!(corridor.camera_height_m > 0.0 && corridor.camera_height_m < corridor.height_m)) {
    fail("scene.corridor.camera_height_m", "must be between the floor and the ceiling");
  }

  const SinusoidMotionConfig& sinusoid = motion.sinusoid;
  at_least(sinusoid.max_rotation_deg, 0.0, "motion.sinusoid.max_rotation_deg");
  if (sinusoid.max_rotation_deg >= 180.0) fail("motion.sinusoid.max_rotation_deg", "must be < 180");
  at_least(sinusoid.max_translation_m, 0.0, "motion.sinusoid.max_translation_m");
  // Below 2 frames a sampled sinusoid aliases into a slower one.
  at_least(sinusoid.period_min_frames, 2.0, "motion.sinusoid.period_min_frames");
  if (!(sinusoid.period_max_frames >= sinusoid.period_min_frames) || !std::isfinite(sinusoid.period_max_frames)) {
    fail("motion.sinusoid.period_max_frames", "must be finite and >= motion.sinusoid.period_min_frames");
  }
  const LoopMotionConfig& loop = motion.loop;
  at_least(loop.radius_x_m, 0.0, "motion.loop.radius_x_m");
  at_least(loop.radius_z_m, 0.0, "motion.loop.radius_z_m");
  at_least(loop.yaw_amplitude_deg, 0.0, "motion.loop.yaw_amplitude_deg");
  if (loop.yaw_amplitude_deg >= 90.0) fail("motion.loop.yaw_amplitude_deg", "must be < 90");
  at_least(loop.wobble_height_m, 0.0, "motion.loop.wobble_height_m");
  at_least(loop.wobble_deg, 0.0, "motion.loop.wobble_deg");
  if (loop.wobble_deg >= 45.0) fail("motion.loop.wobble_deg", "must be < 45");
  const ForwardMotionConfig& forward = motion.forward;
  at_least(forward.step_m, 0.0, "motion.forward.step_m");
  at_least(forward.wobble_m, 0.0, "motion.forward.wobble_m");
  at_least(forward.wobble_deg, 0.0, "motion.forward.wobble_deg");
  if (forward.wobble_deg >= 45.0) fail("motion.forward.wobble_deg", "must be < 45");
  // The shortest drawn period is half of this: keep it >= 2 frames (no aliasing).
  at_least(forward.wobble_period_frames, 4.0, "motion.forward.wobble_period_frames");

  // The outlier sampler draws segments of at least min_length_px inside the image.
  at_least(observation.min_length_px, 0.0, "observation.min_length_px");
  if (observation.min_length_px > 0.5 * std::min(rig.width, rig.height)) {
    fail("observation.min_length_px", "must be at most half the smaller image side");
  }
  positive(observation.min_depth_m, "observation.min_depth_m");

  at_least(noise.endpoint_px, 0.0, "noise.endpoint_px");
  if (!(noise.slide_fraction >= 0.0 && noise.slide_fraction < 0.5)) {
    fail("noise.slide_fraction", "must be in [0, 0.5)");
  }
  if (!(outliers.rate >= 0.0 && outliers.rate <= 1.0)) fail("outliers.rate", "must be in [0, 1]");
}

SimulationConfig SimulationConfigFromJson(const nlohmann::json& j, const std::string& where) {
  SimulationConfig c;
  JsonReader r(j, where);
  r.Get("seed", &c.seed);
  {
    JsonReader s = r.Child("seeds");
    GetSeedOverride(s, "scene", &c.seeds.scene);
    GetSeedOverride(s, "motion", &c.seeds.motion);
    GetSeedOverride(s, "noise", &c.seeds.noise);
    GetSeedOverride(s, "outliers", &c.seeds.outliers);
    s.RejectUnknownKeys();
  }
  r.Get("frames", &c.frames);
  r.Get("frame_rate", &c.frame_rate);
  if (const nlohmann::json* rig = r.Find("rig")) c.rig = StereoRigFromJson(*rig, where, "rig");
  r.Get("focal_error_px", &c.focal_error_px);
  r.Get("max_features", &c.max_features);

  {
    JsonReader s = r.Child("scene");
    GetEnum(s, "type", kSceneTypes, &c.scene.type);
    JsonReader paper = s.Child("paper");
    paper.Get("lines", &c.scene.paper.lines);
    paper.Get("min_length_m", &c.scene.paper.min_length_m).Get("max_length_m", &c.scene.paper.max_length_m);
    GetVector3(paper, "box_center_m", &c.scene.paper.box_center_m);
    GetVector3(paper, "box_size_m", &c.scene.paper.box_size_m);
    paper.Get("cuboid_fraction", &c.scene.paper.cuboid_fraction);
    paper.RejectUnknownKeys();
    JsonReader room = s.Child("room");
    room.Get("width_m", &c.scene.room.width_m)
        .Get("depth_m", &c.scene.room.depth_m)
        .Get("height_m", &c.scene.room.height_m)
        .Get("camera_height_m", &c.scene.room.camera_height_m);
    room.RejectUnknownKeys();
    JsonReader corridor = s.Child("corridor");
    corridor.Get("width_m", &c.scene.corridor.width_m)
        .Get("height_m", &c.scene.corridor.height_m)
        .Get("length_m", &c.scene.corridor.length_m)
        .Get("camera_height_m", &c.scene.corridor.camera_height_m);
    corridor.RejectUnknownKeys();
    s.RejectUnknownKeys();
  }
  // The scene-dependent defaults: each scene with the motion and observation model it is for.
  c.motion.type = DefaultMotionFor(c.scene.type);
  c.observation.clip_to_image = c.scene.type != SceneType::kPaper;
  {
    JsonReader m = r.Child("motion");
    GetEnum(m, "type", kMotionTypes, &c.motion.type);
    JsonReader sinusoid = m.Child("sinusoid");
    sinusoid.Get("max_rotation_deg", &c.motion.sinusoid.max_rotation_deg)
        .Get("max_translation_m", &c.motion.sinusoid.max_translation_m)
        .Get("period_min_frames", &c.motion.sinusoid.period_min_frames)
        .Get("period_max_frames", &c.motion.sinusoid.period_max_frames);
    sinusoid.RejectUnknownKeys();
    JsonReader loop = m.Child("loop");
    loop.Get("radius_x_m", &c.motion.loop.radius_x_m)
        .Get("radius_z_m", &c.motion.loop.radius_z_m)
        .Get("yaw_amplitude_deg", &c.motion.loop.yaw_amplitude_deg)
        .Get("wobble_height_m", &c.motion.loop.wobble_height_m)
        .Get("wobble_deg", &c.motion.loop.wobble_deg);
    loop.RejectUnknownKeys();
    JsonReader forward = m.Child("forward");
    forward.Get("step_m", &c.motion.forward.step_m)
        .Get("wobble_m", &c.motion.forward.wobble_m)
        .Get("wobble_deg", &c.motion.forward.wobble_deg)
        .Get("wobble_period_frames", &c.motion.forward.wobble_period_frames);
    forward.RejectUnknownKeys();
    m.RejectUnknownKeys();
  }
  {
    JsonReader o = r.Child("observation");
    o.Get("clip_to_image", &c.observation.clip_to_image)
        .Get("min_length_px", &c.observation.min_length_px)
        .Get("min_depth_m", &c.observation.min_depth_m);
    o.RejectUnknownKeys();
  }
  {
    JsonReader n = r.Child("noise");
    GetEnum(n, "model", kNoiseModels, &c.noise.model);
    n.Get("endpoint_px", &c.noise.endpoint_px);
    GetEnum(n, "endpoints", kEndpointModels, &c.noise.endpoints);
    n.Get("slide_fraction", &c.noise.slide_fraction);
    n.RejectUnknownKeys();
  }
  {
    JsonReader o = r.Child("outliers");
    o.Get("rate", &c.outliers.rate);
    o.RejectUnknownKeys();
  }
  r.RejectUnknownKeys();
  c.Check(where);
  return c;
}

nlohmann::json SimulationConfigToJson(const SimulationConfig& c) {
  const PaperSceneConfig& paper = c.scene.paper;
  const RoomSceneConfig& room = c.scene.room;
  const CorridorSceneConfig& corridor = c.scene.corridor;
  const SinusoidMotionConfig& sinusoid = c.motion.sinusoid;
  const LoopMotionConfig& loop = c.motion.loop;
  const ForwardMotionConfig& forward = c.motion.forward;
  return {
      {"seed", c.seed},
      {"seeds",
       {{"scene", SeedToJson(c.seeds.scene)},
        {"motion", SeedToJson(c.seeds.motion)},
        {"noise", SeedToJson(c.seeds.noise)},
        {"outliers", SeedToJson(c.seeds.outliers)}}},
      {"frames", c.frames},
      {"frame_rate", c.frame_rate},
      {"rig", StereoRigToJson(c.rig)},
      {"focal_error_px", c.focal_error_px},
      {"max_features", c.max_features},
      {"scene",
       {{"type", SceneTypeName(c.scene.type)},
        {"paper",
         {{"lines", paper.lines},
          {"min_length_m", paper.min_length_m},
          {"max_length_m", paper.max_length_m},
          {"box_center_m", Vector3ToJson(paper.box_center_m)},
          {"box_size_m", Vector3ToJson(paper.box_size_m)},
          {"cuboid_fraction", paper.cuboid_fraction}}},
        {"room",
         {{"width_m", room.width_m},
          {"depth_m", room.depth_m},
          {"height_m", room.height_m},
          {"camera_height_m", room.camera_height_m}}},
        {"corridor",
         {{"width_m", corridor.width_m},
          {"height_m", corridor.height_m},
          {"length_m", corridor.length_m},
          {"camera_height_m", corridor.camera_height_m}}}}},
      {"motion",
       {{"type", MotionTypeName(c.motion.type)},
        {"sinusoid",
         {{"max_rotation_deg", sinusoid.max_rotation_deg},
          {"max_translation_m", sinusoid.max_translation_m},
          {"period_min_frames", sinusoid.period_min_frames},
          {"period_max_frames", sinusoid.period_max_frames}}},
        {"loop",
         {{"radius_x_m", loop.radius_x_m},
          {"radius_z_m", loop.radius_z_m},
          {"yaw_amplitude_deg", loop.yaw_amplitude_deg},
          {"wobble_height_m", loop.wobble_height_m},
          {"wobble_deg", loop.wobble_deg}}},
        {"forward",
         {{"step_m", forward.step_m},
          {"wobble_m", forward.wobble_m},
          {"wobble_deg", forward.wobble_deg},
          {"wobble_period_frames", forward.wobble_period_frames}}}}},
      {"observation",
       {{"clip_to_image", c.observation.clip_to_image},
        {"min_length_px", c.observation.min_length_px},
        {"min_depth_m", c.observation.min_depth_m}}},
      {"noise",
       {{"model", NoiseModelName(c.noise.model)},
        {"endpoint_px", c.noise.endpoint_px},
        {"endpoints", EndpointModelName(c.noise.endpoints)},
        {"slide_fraction", c.noise.slide_fraction}}},
      {"outliers", {{"rate", c.outliers.rate}}},
  };
}

}  // namespace slt
