// The simulation config: every knob of a synthetic stereo line sequence, with defaults that
// give the paper's protocol (Sec. 5.1): 40 random segments about 0.5 m in front of the rig,
// f = 848.7 px, 0.1 m baseline, smooth random motion of at most 1.2 deg and 0.010 m per frame,
// +-2.5 px uniform endpoint noise, 100 frames. docs/simulation.md lists every field.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "geometry/camera.h"
#include "geometry/distortion.h"

namespace slt {

enum class SceneType { kPaper, kRoom, kCorridor, kStreet };
enum class MotionType { kPaper, kLoop, kForward, kStatic, kPureRotation };
// Motions made like a real camera's (docs/simulation.md, "Motion profiles"); kNone: motion.type.
enum class MotionProfile { kNone, kHandheld, kMav, kCar };
enum class NoiseModel { kUniform, kGaussian };
enum class EndpointModel { kFixed, kSliding };

// The names used in JSON ("paper", "room", ...).
const char* SceneTypeName(SceneType type);
const char* MotionTypeName(MotionType type);
const char* MotionProfileName(MotionProfile profile);
const char* NoiseModelName(NoiseModel model);
const char* EndpointModelName(EndpointModel model);

// The motion a scene is meant for: what motion.type defaults to in a JSON config that does not
// set it (paper -> paper, room -> loop, corridor -> forward, street -> forward; the street is
// meant for motion.profile "car").
MotionType DefaultMotionFor(SceneType type);

// The rig and frame rate a scene is rendered with when a JSON config does not set them: the
// street's is KITTI's grey pair (1241 x 376, f = 718.856 px, baseline 0.537 m, 10 Hz; Geiger et
// al., CVPR 2012), the other scenes' the paper's (StereoRig's defaults, 30 Hz).
StereoRig DefaultRigFor(SceneType type);
double DefaultFrameRateFor(SceneType type);

// scene.paper: N independent random segments with midpoints uniform in a box.
struct PaperSceneConfig {
  int lines = 40;
  double min_length_m = 0.1;
  double max_length_m = 0.3;
  // World = left camera at frame 0 (x right, y down, z forward).
  Eigen::Vector3d box_center_m{0.0, 0.0, 0.5};
  // Sized with the motion's excursion: over 100 frames of the default "paper" motion about
  // 93% of the observed segments cross the image over at least 20 px.
  Eigen::Vector3d box_size_m{0.2, 0.15, 0.2};
  // Fraction of the lines (rounded) that are edges of cuboid pieces (rectangles and box corners,
  // simulator/paper_cuboids.h) instead of independent random segments: scenes with the
  // "primitive configurations" Elqursh & Elgammal's method needs. 0 = the paper's scene.
  double cuboid_fraction = 0.0;
};

// scene.room: a furnished room; the camera starts 0.4 * depth from the back wall, in the
// middle of the width, camera_height_m above the floor, looking at the front wall.
struct RoomSceneConfig {
  double width_m = 5.0;   // along x
  double depth_m = 6.0;   // along z
  double height_m = 2.6;  // floor to ceiling
  double camera_height_m = 1.4;
};

// scene.corridor: a long corridor along +z; the camera starts 2 m from its back end, on its
// centre line, camera_height_m above the floor.
struct CorridorSceneConfig {
  double width_m = 2.0;
  double height_m = 2.5;
  double length_m = 30.0;
  double camera_height_m = 1.5;
};

// scene.street: a town crossing. The main street runs along +z from behind the camera; the
// camera starts in its right lane (lane_offset_m right of the centre line) camera_height_m above
// the road, looking along it. A cross street meets it at right angles crossing_at_m ahead (its
// centre line) and runs main_length_m to both sides; the main street runs on
// beyond the crossing for far_length_m. Both carry two lanes, parking lanes, curbs and
// sidewalks between facades of buildings (storeys, windows, doors, shop fronts), with lamp
// posts, signs and parked cars, under a bright sky. With motion.profile "car" at its defaults
// the camera turns right into the cross street's right lane (docs/simulation.md).
struct StreetSceneConfig {
  double crossing_at_m = 50.0;    // z of the cross street's centre line
  double cross_length_m = 250.0;  // the cross street, from the crossing to each end
  double far_length_m = 60.0;     // the main street beyond the crossing
  double lane_offset_m = 1.75;    // the camera right of the centre line (half a lane)
  double camera_height_m = 1.65;  // above the road (KITTI's camera)
};

struct SceneConfig {
  SceneType type = SceneType::kPaper;
  PaperSceneConfig paper;
  RoomSceneConfig room;
  CorridorSceneConfig corridor;
  StreetSceneConfig street;
};

// motion.sinusoid ("paper" and "pure_rotation"): each twist component of the per-frame
// increment is a sinusoid with random amplitude, period and phase; the amplitudes of the
// rotation (translation) components have a root sum of squares of max_rotation_deg
// (max_translation_m), which bounds the per-frame rotation angle (translation).
struct SinusoidMotionConfig {
  double max_rotation_deg = 1.2;
  double max_translation_m = 0.010;
  double period_min_frames = 20.0;
  double period_max_frames = 60.0;
};

// motion.loop: an ellipse in the horizontal plane that starts at the origin heading along +z
// and turns right, returning exactly to the start pose at the last frame; the camera yaws by
// up to yaw_amplitude_deg and wobbles up/down and in pitch/roll.
struct LoopMotionConfig {
  double radius_x_m = 0.3;
  double radius_z_m = 0.4;
  double yaw_amplitude_deg = 15.0;
  double wobble_height_m = 0.02;
  double wobble_deg = 1.0;
};

// motion.forward: step_m per frame along +z, with sinusoidal wobble of the other five
// components (periods random in [0.5, 1.5] * wobble_period_frames).
struct ForwardMotionConfig {
  double step_m = 0.02;
  double wobble_m = 0.02;
  double wobble_deg = 1.0;
  double wobble_period_frames = 60.0;
};

// motion.handheld: a hand-held rig moved slowly (the paper's real runs, Sec. 5.2): the centre
// and the yaw, pitch and roll sway as sums of slow sinusoids (periods drawn in
// [period_min_s, period_max_s]) started at zero, scaled so that the root mean square speed is
// speed_mps and the root mean square angular rate rate_dps (at 30 Hz: about 1 mm and 0.1 deg per
// frame).
struct HandheldMotionConfig {
  double speed_mps = 0.03;
  double rate_dps = 3.0;
  double period_min_s = 8.0;
  double period_max_s = 30.0;
};

// motion.mav: a micro aerial vehicle indoors (EuRoC-like): from hover at the start pose, a
// random sequence of manoeuvres, each a minimum-jerk move of the centre (to a point within
// +-extent_m of the start, heights included: climbs and descents) and of the yaw (turns of up to
// max_turn_deg), or a hover; each lasts long enough that the peak speed stays within
// max_speed_mps and the peak yaw rate within max_yaw_rate_dps, at least min_segment_s. The body
// tilts into its acceleration as a quadrotor does (pitch and roll = acceleration / g) and
// shivers by hover_jitter_m and hover_jitter_deg.
struct MavMotionConfig {
  double max_speed_mps = 1.0;
  double max_yaw_rate_dps = 90.0;
  double max_turn_deg = 180.0;
  Eigen::Vector3d extent_m{1.2, 0.5, 1.2};
  double min_segment_s = 1.0;
  double hover_probability = 0.15;
  double hover_jitter_m = 0.005;
  double hover_jitter_deg = 0.3;
};

// motion.car: a car on a road, already at speed on the first frame: cruise_speed_mps along +z
// for straight_m, a circular turn of turn_deg (positive: to the right) with radius
// turn_radius_m at turn_speed_mps, then straight on. It brakes at brake_mps2 to reach the turn
// speed where the turn begins and accelerates at accelerate_mps2 after it. The body pitches by
// pitch_per_mps2_deg per m/s^2 of braking (nose down) and rolls by roll_per_mps2_deg per m/s^2
// of lateral acceleration (outwards), plus a suspension shiver of suspension_deg (periods
// 0.5-2 s) and suspension_m up and down. At the defaults the camera turns right into the street
// scene's cross street (scene.street at its defaults).
struct CarMotionConfig {
  double cruise_speed_mps = 12.0;
  double turn_speed_mps = 8.5;
  double straight_m = 31.25;  // street: crossing_at_m - lane_offset_m - turn_radius_m
  double turn_radius_m = 17.0;
  double turn_deg = 90.0;
  double brake_mps2 = 2.0;
  double accelerate_mps2 = 1.5;
  double pitch_per_mps2_deg = 0.1;
  double roll_per_mps2_deg = 0.1;
  double suspension_deg = 0.15;
  double suspension_m = 0.01;
};

struct MotionConfig {
  MotionType type = MotionType::kPaper;
  // When not "none", the profile's motion replaces `type`'s.
  MotionProfile profile = MotionProfile::kNone;
  SinusoidMotionConfig sinusoid;
  LoopMotionConfig loop;
  ForwardMotionConfig forward;
  HandheldMotionConfig handheld;
  MavMotionConfig mav;
  CarMotionConfig car;
};

struct ObservationConfig {
  // false (the paper's idealisation: infinite lines): a segment is observed whenever both
  // endpoints are at least min_depth_m in front of the camera, wherever it projects.
  // true (a real camera): the segment is cut at the plane z = min_depth_m, projected, clipped
  // to the image and dropped when nothing of it is inside.
  bool clip_to_image = false;
  // Segments whose noise-free image (after clipping) is shorter are not observed.
  double min_length_px = 10.0;
  double min_depth_m = 0.05;
  // true: only the parts of a segment not hidden by a surface of the scene are seen (the
  // longest visible piece when an occluder splits it); false: every part in the field of view.
  bool occlusion = false;
};

struct NoiseConfig {
  NoiseModel model = NoiseModel::kUniform;
  // uniform: each endpoint coordinate is offset by U(-endpoint_px, endpoint_px) (the paper's
  // "+-n px"); gaussian: by N(0, endpoint_px^2).
  double endpoint_px = 2.5;
  // fixed: the observed endpoints are the projections of the 3-D endpoints in every frame;
  // sliding: in every frame and image the observed segment is the projection of a random
  // sub-interval [s0, s1] of the 3-D segment, s0 ~ U(0, f), s1 ~ U(1 - f, 1), f = slide_fraction.
  EndpointModel endpoints = EndpointModel::kFixed;
  double slide_fraction = 0.25;
};

struct OutlierConfig {
  // Probability that an observed segment (any image, any frame, the first included) is
  // replaced by a random segment in the image with the same id: a wrong match or track.
  double rate = 0.0;
};

// images: how the scene is drawn when images are rendered (render/, `simulate --images`);
// docs/rendering.md gives the image formation model. The image size is the rig's.
struct ImageConfig {
  // Image formation, in the order applied: exposure (gain), vignetting, defocus blur, noise.
  double exposure_variation = 0.05;  // per-frame gain 1 + this * a smooth random wave in [-1, 1]
  // Auto-exposure: every auto_exposure_interval_frames (drawn in [0.5, 1.5] times it) the gain
  // steps by a factor drawn in [1 - auto_exposure_step, 1 + auto_exposure_step], reached over
  // auto_exposure_ramp_frames frames (linear). 0 = off. Both cameras share it.
  double auto_exposure_step = 0.0;
  double auto_exposure_interval_frames = 15.0;
  int auto_exposure_ramp_frames = 3;
  double vignetting = 0.2;           // fraction of the brightness lost at the image corners
  double defocus_blur_px = 0.5;      // standard deviation of a Gaussian blur, px (0 = sharp)
  int motion_blur_samples = 1;       // renders averaged over the exposure (1 = no motion blur)
  double exposure_time_frames = 0.5; // open shutter, as a fraction of the frame interval
  double read_noise = 1.5;           // standard deviation of the Gaussian noise, grey levels
  double shot_noise = 0.03;          // photon noise: variance = read_noise^2 + shot_noise * level
  // Radial-tangential lens distortion [k1, k2, p1, p2] of both cameras (geometry/distortion.h),
  // written into sensor.yaml; the ground-truth observations stay those of the pinhole rig.
  RadialTangential distortion{};
};

// Per-stream base seeds; an unset one follows SimulationConfig::seed.
struct SeedOverrides {
  std::optional<std::uint64_t> scene;
  std::optional<std::uint64_t> motion;
  std::optional<std::uint64_t> noise;
  std::optional<std::uint64_t> outliers;
  std::optional<std::uint64_t> images;
};

struct SimulationConfig {
  std::uint64_t seed = 1;
  SeedOverrides seeds;
  int frames = 100;
  double frame_rate = 30.0;  // Hz; frame k is at time k / frame_rate
  StereoRig rig;             // the true rig the images are made with
  // Added to fx and fy of both cameras in the rig given to the tracker (paper Fig. 5).
  double focal_error_px = 0.0;
  // Keep only the lines with id < max_features (0 = all), so that a sweep over the feature
  // count uses nested sets of lines.
  int max_features = 0;
  SceneConfig scene;
  MotionConfig motion;
  ObservationConfig observation;
  NoiseConfig noise;
  OutlierConfig outliers;
  ImageConfig images;

  // The base seed of each random stream.
  std::uint64_t SceneSeed() const { return seeds.scene.value_or(seed); }
  std::uint64_t MotionSeed() const { return seeds.motion.value_or(seed); }
  std::uint64_t NoiseSeed() const { return seeds.noise.value_or(seed); }
  std::uint64_t OutlierSeed() const { return seeds.outliers.value_or(seed); }
  std::uint64_t ImageSeed() const { return seeds.images.value_or(seed); }
  // The rig given to the tracker: `rig` with focal_error_px added to every focal length.
  StereoRig TrackerRig() const;

  // Throws ConfigError "<where>: key '<dotted.key>': <reason>" for the first invalid field.
  void Check(const std::string& where = "simulation config") const;
};

// Missing keys keep their defaults, unknown keys and invalid values throw ConfigError naming
// `where` and the key. Three defaults follow scene.type: motion.type is DefaultMotionFor(it),
// and observation.clip_to_image and observation.occlusion are true for the structured scenes
// (the paper's protocol keeps its infinite, unoccluded lines; a room seen without clipping
// would observe every wall at once).
SimulationConfig SimulationConfigFromJson(const nlohmann::json& j, const std::string& where);
// Every field, defaults filled in; unset seed overrides are null.
// SimulationConfigFromJson(SimulationConfigToJson(c)) == c.
nlohmann::json SimulationConfigToJson(const SimulationConfig& config);

}  // namespace slt
