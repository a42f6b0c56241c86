// Ceres's glog output, shared by every Ceres solve of the trackers (the Taylor baseline's window,
// the trifocal EKF's reference refinement).
#pragma once

namespace slt {

// Ceres reports a linear solve that failed (a step that Levenberg-Marquardt then retries with
// more damping, e.g. "Linear solver failure ... dense Cholesky") as a glog WARNING on stderr.
// With a robust loss a line or a pose can be left with nearly no weight and the reduced system
// not numerically positive definite, often enough to flood the experiments' output: this shows
// only errors. Idempotent and thread-safe; call before a tracker's first solve (constructors).
void ShowOnlyCeresErrors();

}  // namespace slt
