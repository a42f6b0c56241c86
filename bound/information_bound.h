// The accuracy a causal line tracker could reach at all on a simulated sequence (issue 16,
// docs/long_sequences.md): a reference estimator, not a tracker. A full-history bundle
// adjustment of every simulated observation,
//     min over M_f (f observed), L_i   sum_f sum_{i seen in f} sum_{c in {left, right}} |r(C_c M_f, L_i; s_fic)|^2,
// with r the endpoint-distance residual of a segment (optim/taylor_segment_cost.h,
// SegmentResidual::kEndpoints: the two endpoints' signed distances to the projected line over
// the endpoint noise, the likelihood's residual for independent endpoint noise), M_f the left
// camera's cam_from_world, C_left = I, C_right = the rig's right_from_left (fixing the scale),
// M_0 held at the identity (the gauge: world = the first left camera), lines on the 4-dof
// manifold and poses on SE(3) (optim/line_sfm_manifolds.h), no robust loss (the simulation has
// no outliers unless configured), associated by their ids, and started from the ground truth.
// Every line takes part, the ones the stereo pair does not define included, once the frames
// of the solve determine it: the smallest eigenvalue of its information (poses known) at least
// 1 / line_gate_sigma^2 in its tangent's units (rad, m).
//
// Evaluated at keyframes k = 0, interval, 2 interval, ... and the last frame:
//   causal:   the pose of frame k from the solve over frames 0..k (what a tracker at k could know);
//   smoother: the pose of frame k from the solve over the whole sequence.
// The restrictions give the bound one of the tracker's limits at a time (its residual, the
// lines it leaves out, the frames that refine its structure, its window).
#pragma once

#include <string>
#include <vector>

#include "common/options.h"
#include "geometry/rigid3.h"
#include "simulator/simulator.h"

namespace slt {

// Every field's key, range and doc are declared once, in InformationBoundOptionsSchema().
struct InformationBoundOptions {
  int keyframe_interval = 10;
  double endpoint_sigma_px = 0.57735026918962573;  // 1/sqrt(3): uniform +-1 px
  double line_gate_sigma = 0.1;
  int max_iterations = 30;
  bool causal = true;
  bool smoother = true;
  // Each causal solve starts from the previous one's estimate (new blocks from the truth):
  // the same minimum, reached in fewer iterations.
  bool warm_start = true;
  // Restrictions (all off: the bound).
  bool taylor_residual = false;        // Taylor's segment residual (weight 1) as the tracker's refinement
  double min_epipolar_angle_deg = 0.0;  // leave out lines within this of the epipolar direction at first stereo sight
  int structure_interval = 1;           // only frames f % structure_interval == 0 (and the evaluated one) observe
  int window_frames = 0;                // causal: only the last window_frames frames (0 = all)

  void Check(const std::string& where = "information bound options", const std::string& path = "") const;
};

const OptionSchema<InformationBoundOptions>& InformationBoundOptionsSchema();

struct InformationBound {
  std::vector<int> frames;                      // the keyframes
  std::vector<Rigid3d> causal_cam_from_world;   // per keyframe (empty unless options.causal)
  std::vector<Rigid3d> smoother_cam_from_world; // per keyframe (empty unless options.smoother)
  int iterations = 0;  // Levenberg-Marquardt iterations over every solve
  int unsolved = 0;  // solves that failed or could not place their last frame (that pose is the truth)
};

InformationBound ComputeInformationBound(const SimulatedSequence& sim, const InformationBoundOptions& options);

}  // namespace slt
