// Options of the image front end (docs/frontend.md): line detection, stereo matching and
// temporal tracking. Every field has a default; the JSON keys, ranges and one-line docs are
// declared once in FrontEndOptionsSchema() (frontend_options.cc). A `--config frontend.json`
// holds {"detection": {...}, "matching": {...}, "tracking": {...}, "motion": {...}}, each key
// optional.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "common/options.h"

namespace slt {

// The line detectors of OpenCV 4.6 (with contrib) and the paper's Canny-based path.
enum class LineDetectorType {
  kLsd,               // cv::createLineSegmentDetector (von Gioi et al., PAMI 2010)
  kEdlines,           // cv::ximgproc::EdgeDrawing::detectLines (Akinlar & Topal, PRL 2011)
  kFld,               // cv::ximgproc::FastLineDetector (Lee et al., ICRA 2014)
  kBinaryDescriptor,  // cv::line_descriptor::BinaryDescriptor::detect (EDLines inside, LBD's detector)
  kCannyHough,        // Canny edges, then cv::HoughLinesP (paper Sec. 3.1: "the Canny algorithm")
};

struct DetectionOptions {
  // EDLines by the measurements of docs/frontend.md: at edlines_gradient_threshold 12, with the
  // second-edge search, it finds more of the rendered rooms' and corridor's edges than LSD at
  // the same precision, in under half of LSD's time per image. (LSD was the default while the
  // stereo EKF's start on KITTI, which its lines happened to suit, was tuned for the paper's
  // slow motion: the platform's prior is now the dataset's, docs/datasets.md.)
  LineDetectorType detector = LineDetectorType::kEdlines;
  // LSD's bound on the gradient quantisation error (von Gioi et al.; OpenCV's `quant`): pixels
  // with a gradient magnitude below quant / sin(22.5 deg) are not used. Below OpenCV's 2 it
  // finds more low-contrast edges; alone (quant 1) their imprecision cost stereo matches and
  // the end-to-end loop's ATE, with snap_detections 1.5 gains corridor recall at no cost
  // (docs/frontend.md).
  double lsd_quant = 1.5;
  // LSD's working scale (OpenCV's `scale`, its default 0.8): the image is Gaussian-filtered
  // (sigma = 0.6 / scale) and resampled by it before detection, the segments scaled back. 0.6
  // detects in 0.56 x the pixels of 0.8 (about 40 % less time); the coarser segments are made
  // precise by snap_detections.
  double lsd_scale = 0.6;
  // LSD's refinement (OpenCV's LSD_REFINE_STD: arcs split into straight pieces) or none.
  bool lsd_refine = true;
  // LSD's other parameters (von Gioi et al. 2010; OpenCV's names and defaults): the Gaussian
  // filter's sigma is lsd_sigma_scale / lsd_scale (sigma_scale 0.5 gained 0.6 points of recall
  // on the rendered sequences but lost the KITTI excerpt's tracking test: docs/frontend.md); a
  // pixel joins a line-support region when its level-line angle is within lsd_angle_deg of the
  // region's; with lsd_refine, regions whose rectangle holds under lsd_density of aligned pixels
  // are cut down. OpenCV's log_eps is not an option: it computes the NFA only in its advanced
  // refinement (LSD_REFINE_ADV), which lsd_refine never selects, so it has no effect here
  // (docs/frontend.md: log_eps +-1 changed nothing); OpenCV's default 0 is passed.
  double lsd_sigma_scale = 0.6;
  double lsd_angle_deg = 22.5;
  double lsd_density = 0.7;
  // EDLines' gradient threshold (OpenCV's EdgeDrawing GradientThresholdValue, its default 20):
  // pixels whose gradient (Prewitt, on the image smoothed with sigma 1) is below it are not
  // edge candidates. The rendered rooms' missed edges are weak steps of 5-10 grey levels
  // (docs/frontend.md, the audit of the misses); 12 finds most of them at no loss of precision.
  int edlines_gradient_threshold = 12;
  // Move each detected segment onto the image's edge by the tracker's edge snap
  // (tracking.snap_*, line_tracking.h: SnapDetections) and drop those it cannot place; not
  // when the snap is off (tracking.snap_radius_px 0).
  bool snap_detections = true;
  // Segments shorter than this (after merging) are dropped: too short to track or describe.
  double min_length_px = 30.0;
  // Collinear fragments are merged when their directions differ by less than merge_angle_deg,
  // each one's endpoints lie within merge_distance_px of the other's line, and the gap between
  // them along the line is at most merge_gap_px (overlapping fragments have a negative gap).
  double merge_angle_deg = 2.0;
  double merge_distance_px = 1.5;
  double merge_gap_px = 6.0;
  // Merge only fragments with the same brighter side (each oriented by its gradient first): a
  // merge across a change of polarity makes a segment whose contrast averages out and which
  // the contrast filter and the snap then drop (docs/frontend.md, the audit of the misses).
  bool merge_same_polarity = true;
  // Look for second, parallel edges up to this far (px) beside each detection (parallel_edges.h:
  // the two edges of a thin board, 2-4 px apart, often one weak, which a detector on the
  // smoothed image finds as one, in the mean intensity profile across the detection); 0 = off.
  // 3.5 px: the pairs 2-4 px apart (with LSD, 4-5 px gained 0.1-0.5 points of room recall but
  // failed the KITTI excerpt's prediction test); EDLines, the default, also misses the weaker
  // edge of a pair, and without the search finds under 90 % of the rendered room's edges
  // (docs/frontend.md).
  double parallel_edge_px = 3.5;
  // Mean grey-level difference between the two sides of a segment (sampled 2 px off it; for a
  // second edge, its own step in the profile) below which it is dropped: without a brighter
  // side it has no orientation to match by. 5: a step above the rendered images' noise of a
  // two-pixel difference (sqrt(2) 2.2 grey levels), which the line-averaged profile of a
  // second edge resolves (8 before the second edges; LSD at lsd_quant 1.5 reports no segment
  // between 5 and 8, so with LSD it acts on the second edges only: docs/frontend.md).
  double min_contrast = 5.0;
};

struct MatchingOptions {
  // Photometric cross-correlation of the bands along the two segments (paper Sec. 3.1: > 0.6).
  double min_ncc = 0.6;
  // Half width of the band across each segment that the correlation compares, in pixels.
  int ncc_half_width_px = 3;
  // Largest Euclidean distance between the two MSLD descriptors (unit vectors, 72 values).
  double max_msld_distance = 0.6;
  // The best candidate must be this much closer in MSLD distance than the second best, both
  // ways (Lowe's ratio test, at his 0.8; 1 = off): among look-alike lines (the paper scene's
  // bars, docs/frontend.md) a best candidate barely better than the next is a guess.
  double msld_ratio = 0.8;
  // Overlap of the two segments inside each other's epipolar beam, as a fraction of the shorter
  // one (the beam constraint of Sec. 3.1 asks for a non-empty overlap).
  double min_overlap = 0.5;
  // The same overlap as a fraction of the union of the two extents (0 = off): segments of one
  // 3-D line cover the same rows in both images unless an end is occluded or clipped, a pair of
  // two different lines that share some rows rarely does. Asked only of the pairs that no
  // earlier pair verifies (max_previous_px below): the verification tells the two apart and
  // keeps the pairs with an end hidden in one image, which this test loses (docs/frontend.md,
  // the fourteenth pass).
  double min_union_overlap = 0.0;
  // Temporal verification (stereo_matching.h, SeenInPreviousPair; 0 = off): a new match's 3-D
  // line, moved into an earlier stereo pair by the camera motion between them, must lie within
  // this distance of an edge in both earlier images; px. With a tracker that measures its
  // motion (image_tracking.h), new lines are then matched in the previous pair and checked
  // against the previous_pairs pairs before it by the measured motions, the uniqueness tests
  // weighing only the candidates that pass (stereo_frontend.h); otherwise (the first pairs, a
  // lost frame) the chosen matches are checked against the previous pair by the predicted
  // motion.
  double max_previous_px = 0.0;
  int previous_pairs = 1;
  // Disparity range of a rectified rig, pixels (left u minus right u at the same row).
  double min_disparity_px = 0.0;
  double max_disparity_px = 256.0;
  // Lines within this angle of the epipolar direction (horizontal in a rectified rig) lie in an
  // epipolar plane: the beam cannot place them; they match when the right segment lies on the
  // left one's epipolar line within epipolar_distance_px.
  double epipolar_angle_deg = 5.0;
  double epipolar_distance_px = 1.5;
};

struct TrackingOptions {
  // Pyramidal Lucas-Kanade (cv::calcOpticalFlowPyrLK): window side and pyramid levels above
  // the image (0 = the image only).
  int window_px = 9;
  int pyramid_levels = 3;
  // Lucas-Kanade iterations per pyramid level stop after max_iterations or when the update is
  // below epsilon_px. A point on an edge has a poorly determined component along the edge (the
  // aperture problem), which rarely settles below epsilon_px: it runs to max_iterations.
  int max_iterations = 5;
  double epsilon_px = 0.01;
  // Points sampled along each segment: one every point_spacing_px, at least min_points (else
  // the segment is too short to refit) and at most max_points.
  double point_spacing_px = 6.0;
  int min_points = 6;
  int max_points = 6;
  // Robust refit (optim/ransac.h): a point is an inlier within inlier_px of the line. The line
  // is lost when fewer than min_inlier_fraction of its points are inliers or the RMS distance of
  // the inliers exceeds max_rms_px.
  double inlier_px = 1.0;
  double min_inlier_fraction = 0.6;
  double max_rms_px = 0.5;
  // The snap's refit (below) twice drops the edge points farther than this from the fitted
  // line (and loses the line when under snap_min_fraction of the places remain): on sharp
  // edges a tight bound loses a segment whose edge points lie on two edges (another edge met
  // at one end, a crossing line) instead of fitting a line between them.
  double snap_inlier_px = 1.0;
  // A tracked segment shorter than this (e.g. after clipping at the border) is lost.
  double min_length_px = 25.0;
  // Edge snapping after the refit (line_tracking.h): every snap_spacing_px along the refitted
  // segment (at most snap_max_places places), the strongest image gradient across it of the
  // segment's polarity within snap_radius_px (rounded up to whole pixels: the search runs over
  // integer offsets) is located to sub-pixel precision, and the line is refitted to those edge
  // points; the segment is lost when edges are found at fewer than snap_min_fraction of the
  // places. This anchors the line to the current image instead of to its previous position (no
  // drift). 0 = off.
  double snap_radius_px = 2.0;
  double snap_spacing_px = 1.5;
  int snap_max_places = 24;  // on long segments the places are spread out
  double snap_min_fraction = 0.5;
  // Smallest gradient across the line that counts as an edge, grey levels per pixel.
  double snap_min_gradient = 1.0;
  // The snap's line is lost when the standard error of its direction, from the edge points'
  // residuals and spread along it (sigma = rms / sqrt(sum (t - mean t)^2)), exceeds this, deg
  // (0 = off): a short segment on scattered edge points has an undetermined angle, and a wrong
  // one is worse than none to the tracker. Tracked lines only (SnapDetections does not apply
  // it: a new line is checked at its first tracked frame).
  double max_angle_sigma_deg = 0.3;
  // A snapped tracked segment's ends grow along its edge by at most this per frame, px
  // (ExtendAlongEdge, line_tracking.h; 0 = off): the snap only trims, so without growth a
  // segment's extent only shrinks over its track and it is lost as too short while its edge is
  // still long in view. Off by default: with trifocal_line_ekf's default reference policy the
  // longer tracks mean rarer, smaller references (docs/frontend.md, "the paper scene's ATE").
  double extend_max_px = 0.0;
  // A tracked pair is dropped when its segments no longer overlap in each other's epipolar beam
  // by this fraction (stereo consistency), or leave the disparity range.
  double min_stereo_overlap = 0.3;
};

// Where the optical flow of a live line starts its search in the next pair (large motion,
// issue 19; docs/datasets.md measures each step on KITTI).
enum class FlowSeed {
  kNone,        // at the line's previous position (plain pyramidal LK)
  kImage,       // moved as in the last frame (the line's last two positions)
  kPrediction,  // moved as the tracker's predicted camera motion moves its 3-D line (the stereo
                // pair's triangulation); a line the pair cannot place (within
                // matching.epipolar_angle_deg of the epipolar direction, or not in front of the
                // cameras) or a pair without a prediction falls back to kImage
};

struct MotionOptions {
  FlowSeed seed = FlowSeed::kPrediction;
  // Pyramid levels above the image when a line's seed is not a predicted camera motion (the
  // first frames, a tracker without a prediction, lines the pair cannot place): the search
  // must reach further. tracking.pyramid_levels applies to predicted lines. 4: with 3 the
  // first tracked frame of a KITTI run (1.2 m per frame, no prediction yet) can lose or
  // mis-track enough lines to spoil the stereo EKF's start (docs/datasets.md, large motion).
  int unpredicted_pyramid_levels = 4;
  // Descriptor re-matching: when fewer than this fraction of the live lines survive the flow,
  // the pair's lines are detected and stereo-matched, and each lost line is looked for among
  // them by MSLD near its predicted position (frame_matching.h); found, it keeps its id
  // (0 = off).
  double rematch_below_fraction = 0.5;
  // A candidate lies within rematch_distance_px of the predicted segment's line (both
  // endpoints) and rematch_angle_deg of its direction, overlaps it along the line, and its MSLD
  // distance is at most matching.max_msld_distance and passes matching.msld_ratio. Without a
  // camera prediction the distance gate is unpredicted_gate_scale times wider.
  double rematch_distance_px = 10.0;
  double rematch_angle_deg = 5.0;
  double unpredicted_gate_scale = 4.0;
};

struct FrontEndOptions {
  DetectionOptions detection;
  MatchingOptions matching;
  TrackingOptions tracking;
  MotionOptions motion;
  // Detected pairs added per detection, the longest first (0 = all).
  int max_new_lines = 0;
  // A new pair is not added when it duplicates a line already tracked: left segments within
  // this angle and distance (and overlapping).
  double duplicate_angle_deg = 3.0;
  double duplicate_distance_px = 3.0;
};

const OptionSchema<DetectionOptions>& DetectionOptionsSchema();
const OptionSchema<MatchingOptions>& MatchingOptionsSchema();
const OptionSchema<TrackingOptions>& TrackingOptionsSchema();
const OptionSchema<MotionOptions>& MotionOptionsSchema();
const EnumNames<FlowSeed>& FlowSeedNames();
const OptionSchema<FrontEndOptions>& FrontEndOptionsSchema();
const EnumNames<LineDetectorType>& LineDetectorNames();

// Reads {"detection": .., "matching": .., "tracking": .., ...}; missing keys keep their
// defaults; ConfigError "<where>: key '<path>': <reason>" on unknown keys or invalid values.
FrontEndOptions FrontEndOptionsFromJson(const nlohmann::json& json, const std::string& where);
nlohmann::json ToJson(const FrontEndOptions& options);

}  // namespace slt
