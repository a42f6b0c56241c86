// Elqursh & Elgammal's line-based relative pose as a stereo tracker (method `elqursh_three_line`):
// A. Elqursh and A. Elgammal, "Line-based relative pose estimation", CVPR 2011 -- the fourth
// method Lee et al. (Multimedia Systems 2015, Sec. 5.1, Fig. 6, Table 1) compare with.
//
// Each stereo frame t is estimated against a reference pair (the previous frame) and the
// increments are chained, with no motion model -- as the paper describes it, and why it drifts:
//   1. lines are matched by id between the reference pair and the current pair; each reference
//      pair defines a 3-D line (geometry/plucker.h StereoPairLine), whose images in the current
//      pair are compared with the observed segments by the signed distances of their endpoints
//      (px, both images: LineTransferModel, direction reference_to_current, residual
//      endpoint_distance);
//   2. candidate primitive configurations (two parallel lines, a third orthogonal to them) are
//      listed from the reference pair's 3-D line directions (candidate_triplets.h);
//   3. RANSAC (optim/ransac.h) draws candidate triplets; each gives four rotations from the
//      vanishing point of the parallel lines and the orthogonal line in the reference and current
//      left images, and for each the metric translation from the three stereo lines
//      (three_line_solver.h); a line agrees with a pose when the RMS of its four endpoint
//      distances is below inlier_threshold_px (MSAC score); the best pose is refined by
//      Gauss-Newton on its inliers (methods/stereo_ekf/least_squares.h RefinePose, perturbation
//      on the left, docs/conventions.md);
//   4. the pose is accepted when at least max(min_inliers, min_inlier_fraction x the lines
//      measurable) lines agree: cam_t_from_world = cam_t_from_ref * ref_from_world, and frame t
//      becomes the reference. Otherwise the frame is `lost` (never a pose from too small a
//      consensus) and its pose is the constant-velocity prediction
//        cam_t_from_world = exp(v) cam_t-1_from_world,  v <- lost_velocity_decay * v,
//      v the last measured motion per frame (log of cam_from_ref over the frames it spans,
//      geometry/se3.h), as the EKFs and taylor_line_sfm predict. The reference stays, so that
//      the next frame that finds a configuration measures the motion of the lost ones too,
//      unless frame t has at least min_inliers lines of its own and the reference cannot do
//      better: fewer than min_inliers of its lines are still measurable, or none of their
//      triplets is a candidate configuration (the candidates come from the reference's 3-D
//      directions and a later frame matches at most the reference lines this one does), or it
//      has failed max_lost_frames frames in a row (its configurations do not work); then frame t
//      becomes the reference at the predicted pose.
#pragma once

#include <cstdint>
#include <string>

#include "common/options.h"
#include "methods/pose_tracker.h"
#include "methods/trifocal_line_ekf/line_transfer_model.h"
#include "optim/ransac.h"

namespace slt {

struct ElqurshThreeLineOptions {
  // Candidate configurations: the reference pair's 3-D directions of two lines within
  // parallel_tolerance_deg of each other, of the third within orthogonal_tolerance_deg of
  // orthogonal to both (candidate_triplets.h). A stereo direction at +-2.5 px in the paper
  // protocol is off by 2.3 deg in the median, 10 deg at the 90th percentile.
  double parallel_tolerance_deg = 5.0;
  double orthogonal_tolerance_deg = 5.0;
  // A view of a configuration is degenerate (three_line_solver.h) below this angle: between
  // the planes of the parallel lines, and between the orthogonal line's plane and the vanishing
  // direction or its normal.
  double min_view_angle_deg = 1.0;
  // Rotations between a frame and its reference larger than this are rejected. A tracker at
  // video rate never turns that far in a frame (the paper protocol: 1.2 deg), and the bound
  // removes the mirror poses of symmetric configurations: three edges of a rectangle are mapped
  // onto themselves by the half-turn about the edge that joins the other two, so their infinite
  // lines fit the true pose and its mirror equally well (tests/elqursh_three_line_accuracy_test.cc).
  double max_rotation_deg = 45.0;
  // RANSAC: inlier threshold on the RMS endpoint distance of a line over both current images;
  // samples drawn at most, confidence of the adaptive stop, seed of the sampler (reset with the
  // tracker).
  double inlier_threshold_px = 4.0;
  RansacOptions ransac;
  // Gauss-Newton iterations of the refinement on the consensus.
  int refine_iterations = 10;
  // The smallest consensus accepted: at least min_inliers lines and min_inlier_fraction of the
  // lines measurable in the frame.
  int min_inliers = 3;
  double min_inlier_fraction = 0.6;
  // Lost frames measured against one reference before the current frame replaces it (0 = the
  // paper's rule: always the previous frame).
  int max_lost_frames = 10;
  // A lost frame's pose is the constant-velocity prediction from the last measured
  // frame-to-frame motion (the trackers' common policy, LostFrameOptions).
  LostFrameOptions lost;
  // Lines the measurement model (LineTransferModel) can use.
  EpipolarLineOptions epipolar;

  // Throws ConfigError "<where>: key '<field>': ...".
  void Check(const std::string& where = "elqursh_three_line options") const;
};

// Every field's JSON key (the field name), range and one-line doc.
const OptionSchema<ElqurshThreeLineOptions>& ElqurshThreeLineOptionsSchema();

TrackerInfo ElqurshThreeLineInfo();

}  // namespace slt
