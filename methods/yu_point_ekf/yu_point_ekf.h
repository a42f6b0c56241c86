// Baseline: Yu's point-trifocal EKF (method name `yu_point_ekf`): Y. K. Yu, K. H. Wong,
// M. M. Y. Chang et al., "Robust 3-D motion tracking from stereo images: a model-less method",
// IEEE Trans. Instrumentation and Measurement 57(3), 2008. The paper's comparison (Lee et al.
// 2015, Sec. 5.1, Fig. 6 and Table 1) runs it on the endpoints of the line segments.
//
// Measurement model (point_transfer_model.h): per point seen as x, x' in the reference pair
// (I_1, I'_1) and as y, y' in the current pair (I_t, I'_t), with M = cam_from_ref and
// E = right_from_left,
//   y_hat^k  = x^i l'_j T_i^{jk}     T   over (I_1, I'_1, I_t)  = ([I|0], E, M)
//   y'_hat^k = x^i l'_j T''_i^{jk}   T'' over (I_1, I'_1, I'_t) = ([I|0], E, E M)
//   r = [y - y_hat; y' - y'_hat]  (pixels, 4 scalars per point)
// with l' the line through x' perpendicular to the epipolar line of x in I'_1.
// Filter (methods/stereo_ekf, shared with trifocal_line_ekf): constant-velocity twist model,
// EKF update, validation gate, new reference pairs; the same code, another FeatureModel.
//
// Points: each line id seen in both images of a frame gives two stereo point matches, its
// segment's endpoints (pairing rules in point_transfer_model.h). In the synthetic comparison the
// endpoints are the points: with the paper's protocol (fixed endpoints: every frame observes the
// projections of the same 3-D endpoints) they are true point tracks; with sliding endpoints
// (simulator noise.endpoints = "sliding"), as in real images, an endpoint is a different 3-D
// point in every image, the temporal and stereo point correspondences break, and the method's
// error reflects that. A comparison must say which one it used.
//
// Options (JSON): {"preset": "default" | "paper", "filter": {StereoEkfOptions},
//                  "measurement": {PointTransferOptions}}. The "paper" preset is the faithful
// Yu setting (6-D velocity state, one EKF update, fixed R, no RANSAC, no noise adaptation, and
// the same feature-replacement rule as the trifocal-line EKF's paper preset); "default" is the
// improved one, the same filter settings as the trifocal-line EKF's default. Fields given
// explicitly override the preset.
#pragma once

#include "methods/pose_tracker.h"

namespace slt {

TrackerInfo YuPointEkfInfo();

}  // namespace slt
