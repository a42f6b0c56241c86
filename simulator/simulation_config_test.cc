#include "simulator/simulation_config.h"

#include <gtest/gtest.h>

#include <functional>

#include "common/json_reader.h"

namespace slt {
namespace {

std::string ConfigErrorOf(const std::string& text) {
  try {
    SimulationConfigFromJson(nlohmann::json::parse(text), "sim.json");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(SimulationConfig, EmptyObjectIsThePaperProtocol) {
  const SimulationConfig c = SimulationConfigFromJson(nlohmann::json::object(), "sim.json");
  EXPECT_EQ(c.rig.width, 640);
  EXPECT_EQ(c.rig.height, 480);
  for (const PinholeCamera* camera : {&c.rig.left, &c.rig.right}) {
    EXPECT_NEAR(camera->fx, 4.6 / 5.42e-3, 0.01);  // f = 4.6 mm, 5.42 um pixels
    EXPECT_EQ(camera->fy, camera->fx);
    EXPECT_EQ(camera->cx, 320.0);
    EXPECT_EQ(camera->cy, 240.0);
  }
  EXPECT_TRUE(c.rig.right_from_left.rotation.isIdentity(0.0));
  EXPECT_EQ(c.rig.right_from_left.translation, Eigen::Vector3d(-0.1, 0.0, 0.0));
  EXPECT_EQ(c.scene.type, SceneType::kPaper);
  EXPECT_EQ(c.scene.paper.lines, 40);
  EXPECT_EQ(c.scene.paper.box_center_m, Eigen::Vector3d(0.0, 0.0, 0.5));
  EXPECT_EQ(c.motion.type, MotionType::kPaper);
  EXPECT_EQ(c.motion.sinusoid.max_rotation_deg, 1.2);
  EXPECT_EQ(c.motion.sinusoid.max_translation_m, 0.010);
  EXPECT_EQ(c.frames, 100);
  EXPECT_EQ(c.frame_rate, 30.0);
  EXPECT_EQ(c.noise.model, NoiseModel::kUniform);
  EXPECT_EQ(c.noise.endpoint_px, 2.5);
  EXPECT_EQ(c.noise.endpoints, EndpointModel::kFixed);
  EXPECT_FALSE(c.observation.clip_to_image);
  EXPECT_EQ(c.outliers.rate, 0.0);
  EXPECT_EQ(c.focal_error_px, 0.0);
  EXPECT_EQ(c.max_features, 0);
  // The C++ defaults and the JSON defaults are the same thing.
  EXPECT_EQ(SimulationConfigToJson(c), SimulationConfigToJson(SimulationConfig{}));
}

TEST(SimulationConfig, EveryFieldRoundTrips) {
  SimulationConfig c;
  c.seed = 12345678901234ULL;
  c.seeds.noise = 7;
  c.frames = 37;
  c.frame_rate = 15.0;
  c.rig.left.fx = 500.0;
  c.rig.right.cy = 200.0;
  c.rig.right_from_left.translation = Eigen::Vector3d(-0.2, 0.01, 0.0);
  c.focal_error_px = -20.0;
  c.max_features = 12;
  c.scene.type = SceneType::kCorridor;
  c.scene.paper = {7, 0.2, 0.4, {0.1, 0.2, 1.0}, {1.0, 2.0, 3.0}, 0.25};
  c.scene.room = {6.0, 7.0, 3.0, 1.6};
  c.scene.corridor = {2.5, 2.8, 40.0, 1.7};
  c.scene.street = {60.0, 120.0, 40.0, -1.5, 1.2};
  c.motion.type = MotionType::kPureRotation;
  c.motion.profile = MotionProfile::kMav;
  c.motion.handheld = {0.05, 4.0, 5.0, 20.0};
  c.motion.mav = {1.5, 60.0, 120.0, {1.0, 0.3, 0.8}, 2.0, 0.3, 0.01, 0.5};
  c.motion.car = {10.0, 7.0, 30.0, 15.0, -90.0, 1.5, 1.0, 0.2, 0.3, 0.2, 0.02};
  c.motion.sinusoid = {0.5, 0.002, 10.0, 30.0};
  c.motion.loop = {0.5, 0.6, 10.0, 0.05, 2.0};
  c.motion.forward = {0.05, 0.01, 0.5, 40.0};
  c.observation = {true, 20.0, 0.1, true};
  c.noise = {NoiseModel::kGaussian, 1.5, EndpointModel::kSliding, 0.1};
  c.outliers.rate = 0.05;
  c.images = {0.1, 0.2, 10.0, 4, 0.3, 1.0, 4, 0.8, 3.0, 0.1, {-0.2, 0.05, 0.001, -0.002}};
  const nlohmann::json j = SimulationConfigToJson(c);
  EXPECT_EQ(j["seeds"]["noise"], 7);
  EXPECT_TRUE(j["seeds"]["scene"].is_null());
  EXPECT_EQ(SimulationConfigToJson(SimulationConfigFromJson(j, "resolved.json")), j);
  // Every field was changed above (but the rig's, which dataset/ tests, and the other seeds),
  // so a field that FromJson or ToJson forgot would show here.
  const nlohmann::json changed = j.flatten(), defaults = SimulationConfigToJson(SimulationConfig{}).flatten();
  for (const auto& [key, value] : defaults.items()) {
    if (key.rfind("/rig/", 0) == 0 || key.rfind("/seeds/", 0) == 0) continue;
    EXPECT_NE(changed[key], value) << key;
  }
}

TEST(SimulationConfig, StructuredScenesDefaultToTheirMotionAndClipping) {
  const auto read = [](const char* text) { return SimulationConfigFromJson(nlohmann::json::parse(text), "sim.json"); };
  EXPECT_EQ(read(R"({"scene": {"type": "room"}})").motion.type, MotionType::kLoop);
  EXPECT_TRUE(read(R"({"scene": {"type": "room"}})").observation.clip_to_image);
  EXPECT_EQ(read(R"({"scene": {"type": "corridor"}})").motion.type, MotionType::kForward);
  EXPECT_TRUE(read(R"({"scene": {"type": "corridor"}})").observation.clip_to_image);
  const SimulationConfig explicit_choice =
      read(R"({"scene": {"type": "corridor"}, "motion": {"type": "static"}, "observation": {"clip_to_image": false}})");
  EXPECT_EQ(explicit_choice.motion.type, MotionType::kStatic);
  EXPECT_FALSE(explicit_choice.observation.clip_to_image);
  EXPECT_EQ(read(R"({"scene": {"type": "paper"}})").motion.type, MotionType::kPaper);
  EXPECT_FALSE(read(R"({"scene": {"type": "paper"}})").observation.clip_to_image);
  // Occlusion follows the scene too: on in the structured scenes, off in the paper's protocol.
  EXPECT_TRUE(read(R"({"scene": {"type": "room"}})").observation.occlusion);
  EXPECT_TRUE(read(R"({"scene": {"type": "corridor"}})").observation.occlusion);
  EXPECT_FALSE(read(R"({"scene": {"type": "paper"}})").observation.occlusion);
  EXPECT_FALSE(read(R"({"scene": {"type": "room"}, "observation": {"occlusion": false}})").observation.occlusion);
}

TEST(SimulationConfig, SeedOverrides) {
  const SimulationConfig c = SimulationConfigFromJson(
      nlohmann::json::parse(R"({"seed": 5, "seeds": {"scene": 9, "motion": null}})"), "sim.json");
  EXPECT_EQ(c.SceneSeed(), 9u);
  EXPECT_EQ(c.MotionSeed(), 5u);
  EXPECT_EQ(c.NoiseSeed(), 5u);
  EXPECT_EQ(c.OutlierSeed(), 5u);
}

// Values that ended in std::bad_alloc, ran for minutes, or failed only when the outputs were
// written (issue 21) are refused where the config is read.
TEST(SimulationConfig, SizesAreBounded) {
  EXPECT_EQ(ConfigErrorOf(R"({"frames": 1000000000})"), "sim.json: key 'frames': must be in [1, 100000]");
  EXPECT_EQ(ConfigErrorOf(R"({"frame_rate": 1e-308})"), "sim.json: key 'frame_rate': must be in [0.001, 10000]");
  EXPECT_EQ(ConfigErrorOf(R"({"scene": {"type": "corridor", "corridor": {"length_m": 1e308}}})"),
            "sim.json: key 'scene.corridor.length_m': must be in [6, 1000]");
  EXPECT_EQ(ConfigErrorOf(R"({"scene": {"type": "room", "room": {"width_m": 1e6}}})"),
            "sim.json: key 'scene.room.width_m': must be in [4.6, 1000]");
  EXPECT_EQ(ConfigErrorOf(R"({"motion": {"forward": {"step_m": 1e308}}})"),
            "sim.json: key 'motion.forward.step_m': must be in [0, 10]");
  EXPECT_EQ(ConfigErrorOf(R"({"scene": {"paper": {"lines": 2000000000}}})"),
            "sim.json: key 'scene.paper.lines': must be in [1, 100000]");
  EXPECT_EQ(ConfigErrorOf(R"({"scene": {"paper": {"box_size_m": [1, 1, 1e300]}}})"),
            "sim.json: key 'scene.paper.box_size_m': must be finite, each in [0, 1000]");
  EXPECT_EQ(ConfigErrorOf(R"({"frames": 100000, "frame_rate": 10000})"), "");
}

TEST(SimulationConfig, ErrorsNameFileAndKey) {
  EXPECT_EQ(ConfigErrorOf(R"({"noise": {"endpoint_px": -1}})"),
            "sim.json: key 'noise.endpoint_px': must be a finite number >= 0");
  EXPECT_EQ(ConfigErrorOf(R"({"scene": {"type": "forest"}})"),
            "sim.json: key 'scene.type': must be \"paper\", \"room\", \"corridor\" or \"street\"");
  EXPECT_EQ(ConfigErrorOf(R"({"noise": {"endpoint_pix": 1}})"), "sim.json: key 'noise.endpoint_pix': unknown key");
  EXPECT_EQ(ConfigErrorOf(R"({"nosie": {}})"), "sim.json: key 'nosie': unknown key");
  EXPECT_EQ(ConfigErrorOf(R"({"frames": 2.5})"), "sim.json: key 'frames': expected an integer, got 2.5");
  EXPECT_EQ(ConfigErrorOf(R"({"frames": 0})"), "sim.json: key 'frames': must be in [1, 100000]");
  EXPECT_EQ(ConfigErrorOf(R"({"seed": -3})"), "sim.json: key 'seed': expected a non-negative integer, got -3");
  EXPECT_EQ(ConfigErrorOf(R"({"seeds": {"noise": "x"}})"),
            "sim.json: key 'seeds.noise': expected a non-negative integer, got \"x\"");
  EXPECT_EQ(ConfigErrorOf(R"({"scene": {"paper": {"box_size_m": [1, 2]}}})"),
            "sim.json: key 'scene.paper.box_size_m': expected an array of 3 numbers");
  EXPECT_EQ(ConfigErrorOf(R"({"outliers": {"rate": 1.5}})"), "sim.json: key 'outliers.rate': must be in [0, 1]");
  EXPECT_EQ(ConfigErrorOf(R"({"scene": {"paper": {"cuboid_fraction": -0.1}}})"),
            "sim.json: key 'scene.paper.cuboid_fraction': must be in [0, 1]");
  EXPECT_EQ(ConfigErrorOf(R"({"noise": {"endpoint_px": "big"}})"),
            "sim.json: key 'noise.endpoint_px': expected a number, got string");
  EXPECT_EQ(ConfigErrorOf(R"({"focal_error_px": -900})"),
            "sim.json: key 'focal_error_px': makes a focal length of the tracker's rig non-positive");
  EXPECT_EQ(ConfigErrorOf(R"({"motion": {"sinusoid": {"period_min_frames": 30, "period_max_frames": 20}}})"),
            "sim.json: key 'motion.sinusoid.period_max_frames': must be >= "
            "motion.sinusoid.period_min_frames and <= 1e9");
  EXPECT_EQ(ConfigErrorOf(R"({"observation": {"min_length_px": 300}})"),
            "sim.json: key 'observation.min_length_px': must be at most half the smaller image side");
  EXPECT_EQ(ConfigErrorOf(R"({"images": {"vignetting": 1.5}})"), "sim.json: key 'images.vignetting': must be in [0, 1)");
  EXPECT_EQ(ConfigErrorOf(R"({"images": {"motion_blur_samples": 0}})"),
            "sim.json: key 'images.motion_blur_samples': must be in [1, 64]");
  EXPECT_EQ(ConfigErrorOf(R"({"images": {"distortion": [0.1, 0.2, 0.3]}})"),
            "sim.json: key 'images.distortion': expected [k1, k2, p1, p2]");
  EXPECT_EQ(ConfigErrorOf(R"({"images": {"distortion": [0.1, 0.2, 0.3, 2]}})"),
            "sim.json: key 'images.distortion': coefficients must be finite and within (-1, 1)");
  EXPECT_EQ(ConfigErrorOf(R"({"scene": 3})"), "sim.json: key 'scene': expected a JSON object, got number");
  EXPECT_NE(ConfigErrorOf(R"({"rig": {"width": -1}})").find("sim.json: key 'rig"), std::string::npos);
}

TEST(SimulationConfig, CheckCatchesProgrammaticMistakes) {
  SimulationConfig c;
  c.noise.slide_fraction = 0.5;
  EXPECT_THROW(c.Check(), ConfigError);
  c = SimulationConfig{};
  c.scene.room.camera_height_m = 3.0;  // above the ceiling
  EXPECT_THROW(c.Check(), ConfigError);
  EXPECT_NO_THROW(SimulationConfig{}.Check());
}

TEST(SimulationConfig, TrackerRigHasTheFocalError) {
  SimulationConfig c;
  c.focal_error_px = 200.0;
  const StereoRig tracker_rig = c.TrackerRig();
  for (const PinholeCamera* camera : {&tracker_rig.left, &tracker_rig.right}) {
    EXPECT_EQ(camera->fx, c.rig.left.fx + 200.0);
    EXPECT_EQ(camera->fy, c.rig.left.fy + 200.0);
    EXPECT_EQ(camera->cx, c.rig.left.cx);
    EXPECT_EQ(camera->cy, c.rig.left.cy);
  }
  EXPECT_EQ(tracker_rig.right_from_left.translation, c.rig.right_from_left.translation);
}

}  // namespace
}  // namespace slt
