#include "simulator/simulation_config.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "common/json_reader.h"
#include "common/options.h"
#include "dataset/stereo_lines_io.h"

namespace slt {
namespace {

const EnumNames<SceneType>& SceneTypes() {
  static const EnumNames<SceneType> names = {
      {SceneType::kPaper, "paper"},
      {SceneType::kRoom, "room"},
      {SceneType::kCorridor, "corridor"},
      {SceneType::kStreet, "street"}};
  return names;
}
const EnumNames<MotionProfile>& MotionProfiles() {
  static const EnumNames<MotionProfile> names = {{MotionProfile::kNone, "none"},
                                                 {MotionProfile::kHandheld, "handheld"},
                                                 {MotionProfile::kMav, "mav"},
                                                 {MotionProfile::kCar, "car"}};
  return names;
}
const EnumNames<MotionType>& MotionTypes() {
  static const EnumNames<MotionType> names = {{MotionType::kPaper, "paper"},
                                              {MotionType::kLoop, "loop"},
                                              {MotionType::kForward, "forward"},
                                              {MotionType::kStatic, "static"},
                                              {MotionType::kPureRotation, "pure_rotation"}};
  return names;
}
const EnumNames<NoiseModel>& NoiseModels() {
  static const EnumNames<NoiseModel> names = {{NoiseModel::kUniform, "uniform"}, {NoiseModel::kGaussian, "gaussian"}};
  return names;
}
const EnumNames<EndpointModel>& EndpointModels() {
  static const EnumNames<EndpointModel> names = {{EndpointModel::kFixed, "fixed"}, {EndpointModel::kSliding, "sliding"}};
  return names;
}

// Lengths, angles and rates: finite and at least `lo`.
NumberRange FiniteAtLeast(double lo) { return AtLeast(lo).Finite(); }
NumberRange FinitePositive() { return Positive().Finite(); }
// Upper bounds on what sizes the work and the memory of a simulation (docs/simulation.md,
// "Bounds"): beyond them a config ran for minutes or ended in std::bad_alloc. Generous for any
// experiment: 100 000 frames of 49 lines are ~0.5 GB of observations.
constexpr int kMaxFrames = 100000;
constexpr int kMaxPaperLines = 100000;
constexpr double kMaxSceneSizeM = 1000.0;     // room and corridor sides, paper box and segments
constexpr double kMaxStepM = 10.0;            // per-frame translations and wobbles

// A 3-vector field of S.
template <typename S>
OptionSchema<S>&& Vector3Field(OptionSchema<S>&& schema, const std::string& key, Eigen::Vector3d S::*member,
                               const std::string& doc) {
  return std::move(schema).Custom(
      key,
      [key, member](JsonReader& r, S* s) {
        const nlohmann::json* v = r.Find(key);
        if (v == nullptr) return;
        if (!v->is_array() || v->size() != 3 || !(*v)[0].is_number() || !(*v)[1].is_number() ||
            !(*v)[2].is_number()) {
          r.Fail(key, "expected an array of 3 numbers");
        }
        s->*member = {(*v)[0].get<double>(), (*v)[1].get<double>(), (*v)[2].get<double>()};
      },
      [member](const S& s) {
        const Eigen::Vector3d& v = s.*member;
        return nlohmann::json::array({v.x(), v.y(), v.z()});
      },
      "[x, y, z]", doc);
}

std::string FloorToCeiling(double camera_height_m, double height_m) {
  return camera_height_m > 0.0 && camera_height_m < height_m ? "" : "must be between the floor and the ceiling";
}

const OptionSchema<PaperSceneConfig>& PaperSceneSchema() {
  using C = PaperSceneConfig;
  static const OptionSchema<C> schema =
      Vector3Field(Vector3Field(OptionSchema<C>()
                                    .Field("lines", &C::lines, InRange(1, kMaxPaperLines), "random segments")
                                    .Field("min_length_m", &C::min_length_m, InRange(0.0, kMaxSceneSizeM, "(]"), "shortest segment (m)")
                                    .Field("max_length_m", &C::max_length_m, AnyNumber(), "longest segment (m)"),
                                "box_center_m", &C::box_center_m, "centre of the box of midpoints (world, m)"),
                   "box_size_m", &C::box_size_m, "size of that box (m)")
          .Field("cuboid_fraction", &C::cuboid_fraction, InRange(0.0, 1.0),
                 "fraction of the lines on cuboid pieces (rectangles, box corners) instead of random segments")
          .Check("max_length_m",
                 [](const C& c) {
                   return c.max_length_m >= c.min_length_m && c.max_length_m <= kMaxSceneSizeM
                              ? ""
                              : "must be >= scene.paper.min_length_m and <= 1000";
                 })
          .Check("box_center_m", [](const C& c) {
            return c.box_center_m.allFinite() && c.box_center_m.cwiseAbs().maxCoeff() <= kMaxSceneSizeM
                       ? ""
                       : "must be finite, each coordinate within [-1000, 1000]";
          })
          .Check("box_size_m", [](const C& c) {
            return c.box_size_m.allFinite() && !(c.box_size_m.array() < 0.0).any() &&
                           c.box_size_m.maxCoeff() <= kMaxSceneSizeM
                       ? ""
                       : "must be finite, each in [0, 1000]";
          });
  return schema;
}

// The furniture has fixed sizes (a 2 m bookshelf, 2.05 m doors): smaller rooms cannot hold it.
const OptionSchema<RoomSceneConfig>& RoomSceneSchema() {
  using C = RoomSceneConfig;
  static const OptionSchema<C> schema =
      OptionSchema<C>()
          .Field("width_m", &C::width_m, InRange(4.6, kMaxSceneSizeM), "along x (m)")
          .Field("depth_m", &C::depth_m, InRange(4.0, kMaxSceneSizeM), "along z (m)")
          .Field("height_m", &C::height_m, InRange(2.3, kMaxSceneSizeM), "floor to ceiling (m)")
          .Field("camera_height_m", &C::camera_height_m, AnyNumber(), "camera above the floor (m)")
          .Check("camera_height_m", [](const C& c) { return FloorToCeiling(c.camera_height_m, c.height_m); });
  return schema;
}

const OptionSchema<CorridorSceneConfig>& CorridorSceneSchema() {
  using C = CorridorSceneConfig;
  static const OptionSchema<C> schema =
      OptionSchema<C>()
          .Field("width_m", &C::width_m, InRange(1.2, kMaxSceneSizeM), "(m)")
          .Field("height_m", &C::height_m, InRange(2.3, kMaxSceneSizeM), "(m)")
          .Field("length_m", &C::length_m, InRange(6.0, kMaxSceneSizeM), "(m)")
          .Field("camera_height_m", &C::camera_height_m, AnyNumber(), "camera above the floor (m)")
          .Check("camera_height_m", [](const C& c) { return FloorToCeiling(c.camera_height_m, c.height_m); });
  return schema;
}

// The buildings, crossing and car lanes have fixed sizes: the cross street needs room for the
// car's turn, and the main street's first block room for its buildings before the crossing.
const OptionSchema<StreetSceneConfig>& StreetSceneSchema() {
  using C = StreetSceneConfig;
  static const OptionSchema<C> schema =
      OptionSchema<C>()
          .Field("crossing_at_m", &C::crossing_at_m, InRange(20.0, kMaxSceneSizeM),
                 "the cross street's centre line ahead of the start (m)")
          .Field("cross_length_m", &C::cross_length_m, InRange(20.0, kMaxSceneSizeM),
                 "the cross street from the crossing to each end (m)")
          .Field("far_length_m", &C::far_length_m, InRange(20.0, kMaxSceneSizeM),
                 "the main street beyond the crossing (m)")
          .Field("lane_offset_m", &C::lane_offset_m, InRange(-5.0, 5.0), "camera right of the centre line (m)")
          .Field("camera_height_m", &C::camera_height_m, InRange(0.3, 20.0), "camera above the road (m)");
  return schema;
}

const OptionSchema<SceneConfig>& SceneSchema() {
  using C = SceneConfig;
  static const OptionSchema<C> schema = OptionSchema<C>()
                                            .Field("type", &C::type, SceneTypes(), "which scene")
                                            .Child("paper", &C::paper, PaperSceneSchema(), "the paper's random segments")
                                            .Child("room", &C::room, RoomSceneSchema(), "a furnished room")
                                            .Child("corridor", &C::corridor, CorridorSceneSchema(), "a long corridor")
                                            .Child("street", &C::street, StreetSceneSchema(), "a town crossing");
  return schema;
}

const OptionSchema<SinusoidMotionConfig>& SinusoidMotionSchema() {
  using C = SinusoidMotionConfig;
  static const OptionSchema<C> schema =
      OptionSchema<C>()
          .Field("max_rotation_deg", &C::max_rotation_deg, InRange(0.0, 180.0, "[)").Finite(),
                 "bound of the per-frame rotation (deg)")
          .Field("max_translation_m", &C::max_translation_m, InRange(0.0, kMaxStepM), "bound of the per-frame translation (m)")
          // Below 2 frames a sampled sinusoid aliases into a slower one.
          .Field("period_min_frames", &C::period_min_frames, InRange(2.0, 1e9), "shortest period (frames)")
          .Field("period_max_frames", &C::period_max_frames, AnyNumber(), "longest period (frames)")
          .Check("period_max_frames", [](const C& c) {
            return c.period_max_frames >= c.period_min_frames && c.period_max_frames <= 1e9
                       ? ""
                       : "must be >= motion.sinusoid.period_min_frames and <= 1e9";
          });
  return schema;
}

const OptionSchema<LoopMotionConfig>& LoopMotionSchema() {
  using C = LoopMotionConfig;
  static const OptionSchema<C> schema =
      OptionSchema<C>()
          .Field("radius_x_m", &C::radius_x_m, InRange(0.0, kMaxSceneSizeM), "ellipse semi-axis along x (m)")
          .Field("radius_z_m", &C::radius_z_m, InRange(0.0, kMaxSceneSizeM), "ellipse semi-axis along z (m)")
          .Field("yaw_amplitude_deg", &C::yaw_amplitude_deg, InRange(0.0, 90.0, "[)").Finite(), "yaw swing (deg)")
          .Field("wobble_height_m", &C::wobble_height_m, InRange(0.0, kMaxStepM), "up/down wobble (m)")
          .Field("wobble_deg", &C::wobble_deg, InRange(0.0, 45.0, "[)").Finite(), "pitch/roll wobble (deg)");
  return schema;
}

const OptionSchema<ForwardMotionConfig>& ForwardMotionSchema() {
  using C = ForwardMotionConfig;
  static const OptionSchema<C> schema =
      OptionSchema<C>()
          .Field("step_m", &C::step_m, InRange(0.0, kMaxStepM), "forward step per frame (m)")
          .Field("wobble_m", &C::wobble_m, InRange(0.0, kMaxStepM), "sideways wobble (m)")
          .Field("wobble_deg", &C::wobble_deg, InRange(0.0, 45.0, "[)").Finite(), "rotation wobble (deg)")
          // The shortest drawn period is half of this: keep it >= 2 frames (no aliasing).
          .Field("wobble_period_frames", &C::wobble_period_frames, InRange(4.0, 1e9), "wobble period (frames)");
  return schema;
}

const OptionSchema<HandheldMotionConfig>& HandheldMotionSchema() {
  using C = HandheldMotionConfig;
  static const OptionSchema<C> schema =
      OptionSchema<C>()
          .Field("speed_mps", &C::speed_mps, InRange(0.0, 100.0), "root mean square speed (m/s)")
          .Field("rate_dps", &C::rate_dps, InRange(0.0, 1000.0), "root mean square angular rate (deg/s)")
          .Field("period_min_s", &C::period_min_s, InRange(1e-3, 1e6), "shortest sway period (s)")
          .Field("period_max_s", &C::period_max_s, AnyNumber(), "longest sway period (s)")
          .Check("period_max_s", [](const C& c) {
            return c.period_max_s >= c.period_min_s && c.period_max_s <= 1e6
                       ? ""
                       : "must be >= motion.handheld.period_min_s and <= 1e6";
          });
  return schema;
}

const OptionSchema<MavMotionConfig>& MavMotionSchema() {
  using C = MavMotionConfig;
  static const OptionSchema<C> schema =
      Vector3Field(OptionSchema<C>()
                       .Field("max_speed_mps", &C::max_speed_mps, InRange(1e-3, 100.0), "peak speed (m/s)")
                       .Field("max_yaw_rate_dps", &C::max_yaw_rate_dps, InRange(1e-3, 2000.0), "peak yaw rate (deg/s)")
                       .Field("max_turn_deg", &C::max_turn_deg, InRange(0.0, 360.0), "largest turn of one manoeuvre (deg)")
                       .Field("min_segment_s", &C::min_segment_s, InRange(1e-2, 1e4), "shortest manoeuvre (s)")
                       .Field("hover_probability", &C::hover_probability, InRange(0.0, 1.0),
                              "probability that a manoeuvre is a hover"),
                   "extent_m", &C::extent_m, "half-size of the box the centre stays in, around the start (m)")
          .Field("hover_jitter_m", &C::hover_jitter_m, InRange(0.0, 1.0), "shiver of the centre (m)")
          .Field("hover_jitter_deg", &C::hover_jitter_deg, InRange(0.0, 10.0), "shiver of the attitude (deg)")
          .Check("extent_m", [](const C& c) {
            return c.extent_m.allFinite() && !(c.extent_m.array() < 0.0).any() && c.extent_m.maxCoeff() <= kMaxSceneSizeM
                       ? ""
                       : "must be finite, each in [0, 1000]";
          });
  return schema;
}

const OptionSchema<CarMotionConfig>& CarMotionSchema() {
  using C = CarMotionConfig;
  static const OptionSchema<C> schema =
      OptionSchema<C>()
          .Field("cruise_speed_mps", &C::cruise_speed_mps, InRange(0.1, 100.0), "speed on the straights (m/s)")
          .Field("turn_speed_mps", &C::turn_speed_mps, InRange(0.1, 100.0), "speed in the turn (m/s)")
          .Field("straight_m", &C::straight_m, InRange(0.0, 1e5), "straight before the turn (m)")
          .Field("turn_radius_m", &C::turn_radius_m, InRange(1.0, 1e4), "radius of the turn (m)")
          .Field("turn_deg", &C::turn_deg, InRange(-360.0, 360.0), "the turn, positive to the right (deg)")
          .Field("brake_mps2", &C::brake_mps2, InRange(0.01, 20.0), "braking before the turn (m/s^2)")
          .Field("accelerate_mps2", &C::accelerate_mps2, InRange(0.01, 20.0), "acceleration after it (m/s^2)")
          .Field("pitch_per_mps2_deg", &C::pitch_per_mps2_deg, InRange(0.0, 10.0), "pitch per m/s^2 braking (deg)")
          .Field("roll_per_mps2_deg", &C::roll_per_mps2_deg, InRange(0.0, 10.0), "roll per m/s^2 lateral (deg)")
          .Field("suspension_deg", &C::suspension_deg, InRange(0.0, 10.0), "suspension shiver, pitch and roll (deg)")
          .Field("suspension_m", &C::suspension_m, InRange(0.0, 1.0), "suspension shiver, up and down (m)")
          .Check("turn_speed_mps", [](const C& c) {
            return c.turn_speed_mps <= c.cruise_speed_mps ? "" : "must be <= motion.car.cruise_speed_mps";
          });
  return schema;
}

const OptionSchema<MotionConfig>& MotionSchema() {
  using C = MotionConfig;
  static const OptionSchema<C> schema =
      OptionSchema<C>()
          .Field("type", &C::type, MotionTypes(), "which motion (default: the scene's)")
          .Field("profile", &C::profile, MotionProfiles(), "a real camera's motion, replacing type (none: type)")
          .Child("sinusoid", &C::sinusoid, SinusoidMotionSchema(), "paper and pure_rotation")
          .Child("loop", &C::loop, LoopMotionSchema(), "a closed loop")
          .Child("forward", &C::forward, ForwardMotionSchema(), "forward with wobble")
          .Child("handheld", &C::handheld, HandheldMotionSchema(), "profile handheld: slow sway")
          .Child("mav", &C::mav, MavMotionSchema(), "profile mav: a drone's manoeuvres")
          .Child("car", &C::car, CarMotionSchema(), "profile car: a drive with a turn, at speed from the start");
  return schema;
}

const OptionSchema<ObservationConfig>& ObservationSchema() {
  using C = ObservationConfig;
  static const OptionSchema<C> schema =
      OptionSchema<C>()
          .Field("clip_to_image", &C::clip_to_image, "clip segments to the image (default: not for the paper scene)")
          // The outlier sampler draws segments of at least min_length_px inside the image.
          .Field("min_length_px", &C::min_length_px, FiniteAtLeast(0.0), "shorter images are not observed (px)")
          .Field("min_depth_m", &C::min_depth_m, FinitePositive(), "endpoints nearer are cut or not observed (m)")
          .Field("occlusion", &C::occlusion,
                 "only the parts not hidden by a surface are seen (default: not for the paper scene)");
  return schema;
}

const OptionSchema<ImageConfig>& ImageSchema() {
  using C = ImageConfig;
  static const OptionSchema<C> schema =
      OptionSchema<C>()
          .Field("exposure_variation", &C::exposure_variation, InRange(0.0, 1.0, "[)"),
                 "per-frame gain 1 + this * a slow wave in [-1, 1]")
          .Field("auto_exposure_step", &C::auto_exposure_step, InRange(0.0, 0.5),
                 "auto-exposure: largest gain step, as a fraction (0 = off)")
          .Field("auto_exposure_interval_frames", &C::auto_exposure_interval_frames, InRange(1.0, 1e6),
                 "mean frames between auto-exposure steps")
          .Field("auto_exposure_ramp_frames", &C::auto_exposure_ramp_frames, InRange(1, 1000),
                 "frames over which a step is reached")
          .Field("vignetting", &C::vignetting, InRange(0.0, 1.0, "[)"), "brightness lost in the corners (fraction)")
          .Field("defocus_blur_px", &C::defocus_blur_px, FiniteAtLeast(0.0), "Gaussian blur sigma (px, 0 = sharp)")
          .Field("motion_blur_samples", &C::motion_blur_samples, InRange(1, 64),
                 "renders averaged over the exposure (1 = no motion blur)")
          .Field("exposure_time_frames", &C::exposure_time_frames, InRange(0.0, 1.0),
                 "open shutter (fraction of the frame interval)")
          .Field("read_noise", &C::read_noise, FiniteAtLeast(0.0), "Gaussian noise sigma (grey levels)")
          .Field("shot_noise", &C::shot_noise, FiniteAtLeast(0.0), "photon noise variance per grey level")
          .Custom(
              "distortion",
              [](JsonReader& r, C* c) {
                const nlohmann::json* v = r.Find("distortion");
                if (v == nullptr) return;
                if (!v->is_array() || v->size() != 4) r.Fail("distortion", "expected [k1, k2, p1, p2]");
                for (int i = 0; i < 4; ++i) {
                  if (!(*v)[i].is_number()) r.Fail("distortion", "expected [k1, k2, p1, p2] (numbers)");
                  c->distortion[i] = (*v)[i].get<double>();
                }
              },
              [](const C& c) { return nlohmann::json(c.distortion); }, "[k1, k2, p1, p2], |k| < 1",
              "radial-tangential lens distortion of both cameras (zeros: none)",
              [](const C& c) {
                for (const double k : c.distortion) {
                  if (!(std::abs(k) < 1.0)) return std::string("coefficients must be finite and within (-1, 1)");
                }
                return std::string();
              });
  return schema;
}

const OptionSchema<NoiseConfig>& NoiseSchema() {
  using C = NoiseConfig;
  static const OptionSchema<C> schema =
      OptionSchema<C>()
          .Field("model", &C::model, NoiseModels(), "endpoint noise distribution")
          .Field("endpoint_px", &C::endpoint_px, FiniteAtLeast(0.0), "uniform half-width or gaussian sigma (px)")
          .Field("endpoints", &C::endpoints, EndpointModels(), "fixed or sliding endpoints")
          .Field("slide_fraction", &C::slide_fraction, InRange(0.0, 0.5, "[)"), "sliding: how far endpoints slide");
  return schema;
}

const OptionSchema<OutlierConfig>& OutlierSchema() {
  using C = OutlierConfig;
  static const OptionSchema<C> schema =
      OptionSchema<C>().Field("rate", &C::rate, InRange(0.0, 1.0), "probability a segment is replaced by a random one");
  return schema;
}

const OptionSchema<SeedOverrides>& SeedOverridesSchema() {
  using C = SeedOverrides;
  static const OptionSchema<C> schema = [] {
    OptionSchema<C> s;
    for (auto [key, member] : {std::pair{"scene", &C::scene}, std::pair{"motion", &C::motion},
                               std::pair{"noise", &C::noise}, std::pair{"outliers", &C::outliers},
                               std::pair{"images", &C::images}}) {
      std::move(s).Field(key, member, AnyNumber(), "base seed of this stream (null: seed)");
    }
    return s;
  }();
  return schema;
}

const OptionSchema<SimulationConfig>& SimulationSchema() {
  using C = SimulationConfig;
  static const OptionSchema<C> schema =
      OptionSchema<C>()
          .Field("seed", &C::seed, AnyNumber(), "base seed of every stream")
          .Child("seeds", &C::seeds, SeedOverridesSchema(), "per-stream base seeds")
          .Field("frames", &C::frames, InRange(1, kMaxFrames), "frames")
          .Field("focal_error_px", &C::focal_error_px, AnyNumber().Finite(), "added to the tracker's focal lengths")
          .Field("max_features", &C::max_features, AtLeast(0).Note("0 = all lines"), "lines with id < this only")
          .Child("scene", &C::scene, SceneSchema(), "the 3-D lines")
          // The scene-dependent defaults: each scene with the rig, motion and observation model
          // it is for; the keys read after this replace them.
          .OnRead([](C* c) {
            c->rig = DefaultRigFor(c->scene.type);
            c->frame_rate = DefaultFrameRateFor(c->scene.type);
            c->motion.type = DefaultMotionFor(c->scene.type);
            c->observation.clip_to_image = c->scene.type != SceneType::kPaper;
            c->observation.occlusion = c->scene.type != SceneType::kPaper;
          })
          // Frame times k / frame_rate stay well inside the trajectory files' range.
          .Field("frame_rate", &C::frame_rate, InRange(1e-3, 1e4), "Hz")
          .Custom(
              "rig",
              [](JsonReader& r, C* c) {
                if (const nlohmann::json* rig = r.Find("rig")) c->rig = StereoRigFromJson(*rig, r.where(), "rig");
              },
              [](const C& c) { return StereoRigToJson(c.rig); }, "a stereo rig (docs/formats.md)",
              "the rig the images are made with",
              [](const C& c) {
                try {
                  c.rig.Check();
                } catch (const std::invalid_argument& e) {
                  return std::string(e.what());
                }
                return std::string();
              })
          .Child("motion", &C::motion, MotionSchema(), "the camera's motion")
          .Child("observation", &C::observation, ObservationSchema(), "what is observed")
          .Child("noise", &C::noise, NoiseSchema(), "endpoint noise")
          .Child("outliers", &C::outliers, OutlierSchema(), "wrong segments")
          .Child("images", &C::images, ImageSchema(), "rendered images (simulate --images, docs/rendering.md)")
          .Check("frames",
                 [](const C& c) {
                   return c.motion.type == MotionType::kLoop && c.motion.profile == MotionProfile::kNone && c.frames < 2
                              ? "a loop needs at least 2 frames"
                              : "";
                 })
          .Check("focal_error_px",
                 [](const C& c) {
                   for (const PinholeCamera* camera : {&c.rig.left, &c.rig.right}) {
                     if (std::min(camera->fx, camera->fy) + c.focal_error_px <= 0.0) {
                       return "makes a focal length of the tracker's rig non-positive";
                     }
                   }
                   return "";
                 })
          .Check("observation.min_length_px", [](const C& c) {
            return c.observation.min_length_px > 0.5 * std::min(c.rig.width, c.rig.height)
                       ? "must be at most half the smaller image side"
                       : "";
          });
  return schema;
}

}  // namespace

const char* SceneTypeName(SceneType type) { return EnumName(SceneTypes(), type); }
const char* MotionTypeName(MotionType type) { return EnumName(MotionTypes(), type); }
const char* MotionProfileName(MotionProfile profile) { return EnumName(MotionProfiles(), profile); }
const char* NoiseModelName(NoiseModel model) { return EnumName(NoiseModels(), model); }
const char* EndpointModelName(EndpointModel model) { return EnumName(EndpointModels(), model); }

MotionType DefaultMotionFor(SceneType type) {
  switch (type) {
    case SceneType::kPaper: return MotionType::kPaper;
    case SceneType::kRoom: return MotionType::kLoop;
    case SceneType::kCorridor:
    case SceneType::kStreet: return MotionType::kForward;
  }
  return MotionType::kPaper;
}

StereoRig DefaultRigFor(SceneType type) {
  StereoRig rig;
  if (type != SceneType::kStreet) return rig;
  // KITTI odometry's rectified grey pair (calib.txt of sequences 00-02: P0, P1).
  rig.width = 1241;
  rig.height = 376;
  for (PinholeCamera* camera : {&rig.left, &rig.right}) {
    camera->fx = camera->fy = 718.856;
    camera->cx = 607.1928;
    camera->cy = 185.2157;
  }
  rig.right_from_left = Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-386.1448 / 718.856, 0.0, 0.0));
  return rig;
}

double DefaultFrameRateFor(SceneType type) { return type == SceneType::kStreet ? 10.0 : 30.0; }

StereoRig SimulationConfig::TrackerRig() const {
  StereoRig tracker_rig = rig;
  for (PinholeCamera* camera : {&tracker_rig.left, &tracker_rig.right}) {
    camera->fx += focal_error_px;
    camera->fy += focal_error_px;
  }
  return tracker_rig;
}

void SimulationConfig::Check(const std::string& where) const { SimulationSchema().Validate(*this, where, ""); }

SimulationConfig SimulationConfigFromJson(const nlohmann::json& j, const std::string& where) {
  SimulationConfig c;
  JsonReader r(j, where);
  SimulationSchema().ReadFields(r, &c);
  r.RejectUnknownKeys();
  c.Check(where);
  return c;
}

nlohmann::json SimulationConfigToJson(const SimulationConfig& c) { return SimulationSchema().ToJson(c); }

}  // namespace slt
