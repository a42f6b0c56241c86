#include "methods/trifocal_line_ekf/trifocal_line_ekf.h"

#include "methods/stereo_ekf/stereo_ekf_tracker.h"
#include "methods/trifocal_line_ekf/line_transfer_model.h"

namespace slt {
namespace {

std::unique_ptr<PoseTracker> Create(const nlohmann::json& json, const std::string& where) {
  JsonReader reader(json, where);
  std::string preset = "default";
  reader.Get("preset", &preset);
  StereoEkfOptions filter;
  LineTransferOptions measurement;
  if (preset == "paper") {
    filter.state = "velocity";
    filter.max_iterations = 1;
    filter.robust = false;
    filter.adaptive_noise = false;
    filter.min_feature_fraction = 0.0;
    // Sec. 3.3 counts the lines that survive the gate (eq. 20) as the available ones.
    filter.count_features = "gated";
    measurement.residual = "theta_lambda";
    measurement.noise = "fixed";
    measurement.direction = "current_to_reference";
  } else if (preset != "default") {
    reader.Fail("preset", "must be \"default\" or \"paper\"");
  }
  JsonReader filter_reader = reader.Child("filter");
  ReadStereoEkfOptions(filter_reader, &filter);
  filter_reader.RejectUnknownKeys();
  JsonReader measurement_reader = reader.Child("measurement");
  ReadLineTransferOptions(measurement_reader, &measurement);
  measurement_reader.RejectUnknownKeys();
  reader.RejectUnknownKeys();
  return std::make_unique<StereoEkfTracker>(filter, std::make_unique<LineTransferModel>(measurement),
                                            LineTransferOptionsToJson(measurement));
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
