#include "frontend/frontend_options.h"

namespace slt {

const EnumNames<LineDetectorType>& LineDetectorNames() {
  static const EnumNames<LineDetectorType> names = {{LineDetectorType::kLsd, "lsd"},
                                                     {LineDetectorType::kEdlines, "edlines"},
                                                     {LineDetectorType::kFld, "fld"},
                                                     {LineDetectorType::kBinaryDescriptor, "binary_descriptor"},
                                                     {LineDetectorType::kCannyHough, "canny_hough"}};
  return names;
}

const OptionSchema<DetectionOptions>& DetectionOptionsSchema() {
  using D = DetectionOptions;
  static const OptionSchema<D> schema =
      OptionSchema<D>()
          .Field("detector", &D::detector, LineDetectorNames(), "line segment detector")
          .Field("lsd_quant", &D::lsd_quant, InRange(0.1, 10.0), "LSD: gradient quantisation bound (OpenCV's quant)")
          .Field("lsd_scale", &D::lsd_scale, InRange(0.1, 1.0), "LSD: image scale it works on (OpenCV's scale)")
          .Field("lsd_refine", &D::lsd_refine, "LSD: split curved regions into straight pieces (LSD_REFINE_STD)")
          .Field("lsd_sigma_scale", &D::lsd_sigma_scale, InRange(0.1, 5.0), "LSD: Gaussian sigma = this / lsd_scale (OpenCV's sigma_scale)")
          .Field("lsd_angle_deg", &D::lsd_angle_deg, InRange(1.0, 90.0), "LSD: level-line angle tolerance, deg (OpenCV's ang_th)")
          .Field("lsd_density", &D::lsd_density, InRange(0.0, 1.0), "LSD: least density of aligned points in a rectangle (OpenCV's density_th; only with lsd_refine)")
          .Field("edlines_gradient_threshold", &D::edlines_gradient_threshold, InRange(1, 255),
                 "EDLines: least gradient of an edge pixel (OpenCV's GradientThresholdValue)")
          .Field("snap_detections", &D::snap_detections, "move detected segments onto the edge by the tracking snap")
          .Field("min_length_px", &D::min_length_px, InRange(2.0, 1e4), "shortest segment kept, px")
          .Field("merge_angle_deg", &D::merge_angle_deg, InRange(0.0, 45.0), "collinear merge: largest angle, deg")
          .Field("merge_distance_px", &D::merge_distance_px, AtLeast(0.0), "collinear merge: largest endpoint distance to the other line, px")
          .Field("merge_gap_px", &D::merge_gap_px, AtLeast(0.0), "collinear merge: largest gap along the line, px")
          .Field("merge_same_polarity", &D::merge_same_polarity, "collinear merge: only fragments with the same brighter side")
          .Field("parallel_edge_px", &D::parallel_edge_px, InRange(0.0, 10.0), "second edges searched up to this far beside each detection, px (0 = off)")
          .Field("min_contrast", &D::min_contrast, AtLeast(0.0), "smallest grey-level difference between the two sides");
  return schema;
}

const OptionSchema<MatchingOptions>& MatchingOptionsSchema() {
  using M = MatchingOptions;
  static const OptionSchema<M> schema =
      OptionSchema<M>()
          .Field("min_ncc", &M::min_ncc, InRange(-1.0, 1.0), "smallest photometric cross-correlation (paper: 0.6)")
          .Field("ncc_half_width_px", &M::ncc_half_width_px, InRange(1, 20), "half width of the correlated band, px")
          .Field("max_msld_distance", &M::max_msld_distance, InRange(0.0, 2.0, "(]"), "largest MSLD descriptor distance")
          .Field("msld_ratio", &M::msld_ratio, InRange(0.0, 1.0, "(]"), "best / second-best MSLD distance at most (1 = off)")
          .Field("min_overlap", &M::min_overlap, InRange(0.0, 1.0), "overlap in the epipolar beam, fraction of the shorter segment")
          .Field("min_union_overlap", &M::min_union_overlap, InRange(0.0, 1.0), "overlap in the epipolar beam, fraction of the union of the two extents (0 = off)")
          .Field("max_previous_px", &M::max_previous_px, InRange(0.0, 20.0), "temporal check: the match's 3-D line moved into earlier pairs within this of an edge, px (0 = off)")
          .Field("previous_pairs", &M::previous_pairs, InRange(1, 8), "temporal check with a measured motion: the earlier pairs checked")
          .Field("min_disparity_px", &M::min_disparity_px, AnyNumber().Finite(), "smallest disparity of a rectified rig, px")
          .Field("max_disparity_px", &M::max_disparity_px, AnyNumber().Finite(), "largest disparity of a rectified rig, px")
          .Field("epipolar_angle_deg", &M::epipolar_angle_deg, InRange(0.0, 45.0), "lines closer to the epipolar direction are matched along it, deg")
          .Field("epipolar_distance_px", &M::epipolar_distance_px, Positive(), "such a line's right endpoints within this of the left one's epipolar line, px")
          .Check("max_disparity_px", [](const M& m) {
            return m.max_disparity_px > m.min_disparity_px ? "" : "must be > min_disparity_px";
          });
  return schema;
}

const OptionSchema<TrackingOptions>& TrackingOptionsSchema() {
  using T = TrackingOptions;
  static const OptionSchema<T> schema =
      OptionSchema<T>()
          .Field("window_px", &T::window_px, InRange(5, 101), "Lucas-Kanade window side, px")
          .Field("pyramid_levels", &T::pyramid_levels, InRange(0, 8), "pyramid levels above the image")
          .Field("max_iterations", &T::max_iterations, InRange(1, 100), "Lucas-Kanade iterations per pyramid level, at most")
          .Field("epsilon_px", &T::epsilon_px, Positive(), "Lucas-Kanade stops below this update, px")
          .Field("point_spacing_px", &T::point_spacing_px, Positive(), "one tracked point every this many px along a segment")
          .Field("min_points", &T::min_points, InRange(2, 1000), "fewest points per segment")
          .Field("max_points", &T::max_points, InRange(2, 1000), "most points per segment")
          .Field("inlier_px", &T::inlier_px, Positive(), "refit: inlier distance to the line, px")
          .Field("min_inlier_fraction", &T::min_inlier_fraction, InRange(0.0, 1.0), "refit: fewest inliers, fraction of the points")
          .Field("max_rms_px", &T::max_rms_px, Positive(), "refit: largest RMS distance of the inliers, px")
          .Field("min_length_px", &T::min_length_px, InRange(2.0, 1e4), "shortest tracked segment kept, px")
          .Field("snap_radius_px", &T::snap_radius_px, InRange(0.0, 20.0), "edge snapping: search across the line, px, rounded up to whole pixels (0 = off)")
          .Field("snap_spacing_px", &T::snap_spacing_px, InRange(0.5, 100.0), "edge snapping: one search every this many px")
          .Field("snap_max_places", &T::snap_max_places, InRange(3, 1000), "edge snapping: most searches per segment")
          .Field("snap_min_fraction", &T::snap_min_fraction, InRange(0.0, 1.0), "edge snapping: fewest searches finding an edge, fraction")
          .Field("snap_inlier_px", &T::snap_inlier_px, Positive(), "snapping: edge points kept within this of the fitted line, px")
          .Field("snap_min_gradient", &T::snap_min_gradient, AtLeast(0.0), "edge snapping: weakest edge, grey levels per px")
          .Field("max_angle_sigma_deg", &T::max_angle_sigma_deg, AtLeast(0.0), "edge snapping: largest standard error of the line's direction, deg (0 = off)")
          .Field("extend_max_px", &T::extend_max_px, InRange(0.0, 1e4), "growth of a tracked segment's ends along its edge per frame, px (0 = off)")
          .Field("min_stereo_overlap", &T::min_stereo_overlap, InRange(0.0, 1.0), "stereo consistency: overlap in the epipolar beam")
          .Check("max_points", [](const T& t) { return t.max_points >= t.min_points ? "" : "must be >= min_points"; });
  return schema;
}

const EnumNames<FlowSeed>& FlowSeedNames() {
  static const EnumNames<FlowSeed> names = {
      {FlowSeed::kNone, "none"}, {FlowSeed::kImage, "image"}, {FlowSeed::kPrediction, "prediction"}};
  return names;
}

const OptionSchema<MotionOptions>& MotionOptionsSchema() {
  using M = MotionOptions;
  static const OptionSchema<M> schema =
      OptionSchema<M>()
          .Field("seed", &M::seed, FlowSeedNames(), "where the flow starts: previous position, last image motion, or predicted camera motion")
          .Field("unpredicted_pyramid_levels", &M::unpredicted_pyramid_levels, InRange(0, 8), "pyramid levels for lines without a predicted camera motion")
          .Field("rematch_below_fraction", &M::rematch_below_fraction, InRange(0.0, 1.0), "re-match lost lines by MSLD when fewer survive the flow (0 = off)")
          .Field("rematch_distance_px", &M::rematch_distance_px, Positive(), "re-matching: largest distance to the predicted line, px")
          .Field("rematch_angle_deg", &M::rematch_angle_deg, InRange(0.0, 90.0, "(]"), "re-matching: largest angle to the predicted line, deg")
          .Field("unpredicted_gate_scale", &M::unpredicted_gate_scale, AtLeast(1.0), "re-matching: distance gate factor without a camera prediction");
  return schema;
}

const OptionSchema<FrontEndOptions>& FrontEndOptionsSchema() {
  using F = FrontEndOptions;
  static const OptionSchema<F> schema =
      OptionSchema<F>()
          .Child("detection", &F::detection, DetectionOptionsSchema(), "line detection")
          .Child("matching", &F::matching, MatchingOptionsSchema(), "stereo matching")
          .Child("tracking", &F::tracking, TrackingOptionsSchema(), "temporal tracking")
          .Child("motion", &F::motion, MotionOptionsSchema(), "large motion: flow seeds, pyramid depth, re-matching")
          .Field("max_new_lines", &F::max_new_lines, AtLeast(0), "pairs added per detection, longest first (0 = all)")
          .Field("duplicate_angle_deg", &F::duplicate_angle_deg, InRange(0.0, 45.0), "a new pair within this angle of a tracked line ...")
          .Field("duplicate_distance_px", &F::duplicate_distance_px, AtLeast(0.0), "... and this distance duplicates it, px");
  return schema;
}

FrontEndOptions FrontEndOptionsFromJson(const nlohmann::json& json, const std::string& where) {
  JsonReader reader(json, where);
  FrontEndOptions options;
  FrontEndOptionsSchema().Read(reader, &options);
  reader.RejectUnknownKeys();
  return options;
}

nlohmann::json ToJson(const FrontEndOptions& options) { return FrontEndOptionsSchema().ToJson(options); }

}  // namespace slt
