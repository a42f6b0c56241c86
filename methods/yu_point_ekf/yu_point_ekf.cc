#include "methods/yu_point_ekf/yu_point_ekf.h"

#include "methods/stereo_ekf/stereo_ekf_tracker.h"
#include "methods/yu_point_ekf/point_transfer_model.h"

namespace slt {
namespace {

std::unique_ptr<PoseTracker> Create(const nlohmann::json& json, const std::string& where) {
  return CreateStereoEkfTracker<PointTransferOptions>(
      json, where, [](PointTransferOptions* m) { m->noise = MeasurementNoise::kFixed; }, ReadPointTransferOptions,
      PointTransferOptionsToJson, [](const PointTransferOptions& m) { return std::make_unique<PointTransferModel>(m); });
}

}  // namespace

TrackerInfo YuPointEkfInfo() {
  // Two points (8 scalars) determine the pose; one stereo line gives two: minimum_lines 1.
  TrackerInfo info;
  info.name = "yu_point_ekf";
  info.description = "Point-trifocal EKF on segment endpoints (Yu, Wong, Chang et al., IEEE TIM 2008)";
  info.create = Create;
  info.minimum_lines = 1;
  info.list_options = [] { return StereoEkfOptionDocs(PointTransferOptionsSchema()); };
  return info;
}

}  // namespace slt
