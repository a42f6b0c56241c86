#include "methods/trifocal_line_ekf/trifocal_line_ekf.h"

#include "methods/stereo_ekf/stereo_ekf_tracker.h"
#include "methods/trifocal_line_ekf/line_transfer_model.h"

namespace slt {
namespace {

std::unique_ptr<PoseTracker> Create(const nlohmann::json& json, const std::string& where) {
  return CreateStereoEkfTracker<LineTransferOptions>(
      json, where,
      [](LineTransferOptions* m) {
        // The paper's measurement: current lines transferred into the reference view (eq. 16),
        // compared in (theta, lambda) (eq. 8-9) with a fixed R; lines near the trifocal plane
        // excluded (Sec. 4).
        m->residual = "theta_lambda";
        m->noise = "fixed";
        m->direction = "current_to_reference";
        m->min_plane_angle_deg = 3.0;
      },
      ReadLineTransferOptions, LineTransferOptionsToJson,
      [](const LineTransferOptions& m) { return std::make_unique<LineTransferModel>(m); });
}

}  // namespace

TrackerInfo TrifocalLineEkfInfo() {
  TrackerInfo info;
  info.name = "trifocal_line_ekf";
  info.description = "Trifocal-line EKF (Lee, Yu, Wong, Chang, Multimedia Systems 2015)";
  info.create = Create;
  return info;
}

}  // namespace slt
