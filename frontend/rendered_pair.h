// Rendered sequences of frontend_audit.h's configs (default image settings: noise, blur,
// vignetting on), rendered on demand: the scenes of measure_frontend and of the front end's tests
// (the room at the default 640 x 480 rig, the paper scene).
#pragma once

#include "frontend/frontend_audit.h"
#include "render/sequence_renderer.h"
#include "simulator/simulation_config.h"

namespace slt {

// A rendered sequence of frontend_audit.h's configs; only the frames asked for are rendered.
// Neither copied nor moved: the renderer refers to the sequence and config it holds.
class RenderedSequence {
 public:
  explicit RenderedSequence(const nlohmann::json& config)
      : config_(SimulationConfigFromJson(config, "rendered_pair.h")), sequence_(Simulate(config_)), renderer_(sequence_, config_) {}
  RenderedSequence(const RenderedSequence&) = delete;
  RenderedSequence& operator=(const RenderedSequence&) = delete;

  const SimulationConfig& config() const { return config_; }
  const SimulatedSequence& sequence() const { return sequence_; }
  const StereoRig& rig() const { return sequence_.true_rig; }
  cv::Mat Image(int frame, int camera) const { return renderer_.Image(frame, camera); }
  ProjectedGroundTruth Projected(int frame, int camera) const { return ProjectedGroundTruthAt(sequence_, frame, camera); }
  // The left camera's motion from frame `from` to frame `to`, to_from_from.
  Rigid3d Motion(int from, int to) const {
    return sequence_.ground_truth[to].world_from_cam.Inverse() * sequence_.ground_truth[from].world_from_cam;
  }

 private:
  SimulationConfig config_;
  SimulatedSequence sequence_;
  SequenceRenderer renderer_;
};

// The 200-frame room loop (about 1 cm and 0.3 deg per frame).
class RenderedRoom : public RenderedSequence {
 public:
  RenderedRoom() : RenderedSequence(RenderedRoomConfig(200, false)) {}
};

// The paper's scene and motion (Sec. 5.1; floating bright bars, up to 1 cm and 1 deg per frame).
class RenderedPaper : public RenderedSequence {
 public:
  explicit RenderedPaper(int frames) : RenderedSequence(RenderedPaperConfig(frames)) {}
};

}  // namespace slt
