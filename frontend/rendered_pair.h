// For the front end's tests: a short rendered room sequence (frontend_audit.h's room at the
// default 640 x 480 rig; default image settings: noise, blur, vignetting on), rendered on demand.
#pragma once

#include "frontend/frontend_audit.h"
#include "render/sequence_renderer.h"
#include "simulator/simulation_config.h"

namespace slt {

// The 200-frame room loop (about 1 cm and 0.3 deg per frame); only the frames asked for are
// rendered.
class RenderedRoom {
 public:
  RenderedRoom()
      : config_(SimulationConfigFromJson(RenderedRoomConfig(200, false), "rendered_pair.h")),
        sequence_(Simulate(config_)),
        renderer_(sequence_, config_) {}

  const SimulatedSequence& sequence() const { return sequence_; }
  const StereoRig& rig() const { return sequence_.true_rig; }
  cv::Mat Image(int frame, int camera) const { return renderer_.Image(frame, camera); }
  ProjectedGroundTruth Projected(int frame, int camera) const { return ProjectedGroundTruthAt(sequence_, frame, camera); }

 private:
  SimulationConfig config_;
  SimulatedSequence sequence_;
  SequenceRenderer renderer_;
};

}  // namespace slt
