// The paper's tracker (method name `trifocal_line_ekf`): Lee, Yu, Wong, Chang, "Tracking 3-D
// motion from straight lines with trifocal tensors", Multimedia Systems 2015.
//
// Measurement model (line_transfer_model.h, eq. 13-17): per line, the two trifocal transfers
// T(l'_1, l_t) and T'(l_t, l'_t) predict the reference line l_1; 4 residual scalars per line.
// Filter (methods/stereo_ekf, eq. 10-12, 18-20): constant-velocity twist model, EKF update,
// validation gate, new reference pairs.
//
// Options (JSON): {"preset": "default" | "paper" | "long_run" | "long_run_consistent",
//                  "filter": {StereoEkfOptions}, "measurement": {LineTransferOptions}}. The
// "paper" preset is the faithful setting (6-D velocity state, one EKF update, (theta, lambda)
// residual, fixed R, no RANSAC); "default" is the improved one; "long_run" adds the joint
// refinement of the reference lines with dense keyframes, for long runs in structured scenes,
// and "long_run_consistent" makes its reported covariance consistent (docs/long_sequences.md).
// Fields given explicitly override the preset.
#pragma once

#include "methods/pose_tracker.h"

namespace slt {

TrackerInfo TrifocalLineEkfInfo();

}  // namespace slt
