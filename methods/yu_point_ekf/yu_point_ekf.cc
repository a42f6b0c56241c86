#include "methods/yu_point_ekf/yu_point_ekf.h"

#include "methods/stereo_ekf/stereo_ekf_tracker.h"
#include "methods/yu_point_ekf/point_transfer_model.h"

namespace slt {

// Two points (8 scalars) determine the pose; one stereo line gives two: minimum_lines 1.
TrackerInfo YuPointEkfInfo() {
  TrackerInfo info = StereoEkfTrackerInfo<PointTransferModel, PointTransferOptions>(
      "yu_point_ekf", "Point-trifocal EKF on segment endpoints (Yu, Wong, Chang et al., IEEE TIM 2008)",
      {{"paper", "the paper's filter (Sec. 3-4) with a fixed R",
        [](StereoEkfOptions* filter, PointTransferOptions* m) {
          ApplyPaperPreset(filter);
          m->noise = MeasurementNoise::kFixed;
        }}},
      ReadPointTransferOptions, PointTransferOptionsToJson, PointTransferOptionsSchema);
  info.minimum_lines = 1;
  return info;
}

}  // namespace slt
