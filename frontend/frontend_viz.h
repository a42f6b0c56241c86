// The pictures of track_images --viz, after the paper's Figs. 7-9 (Sec. 5.2: the recovered
// motion checked by re-projecting the reference lines):
//   detections_first_pair.png   the lines detected in the first stereo pair (Fig. 7 top);
//   reprojection_NNNNNN.png     at a third, two thirds and the end of the run: the segments of
//                               the first pair, their endpoints placed on the 3-D line the
//                               pair triangulates (line_motion.h) and re-projected with the
//                               recovered motion (magenta), next to the same lines as tracked
//                               (green) (Figs. 7-8);
//   reprojection_error.png/.csv the mean angle between tracked and re-projected lines against
//                               frame, both images (Fig. 9).
// Lines within 5 deg of the epipolar direction are not triangulated (their stereo pair does
// not define them). Everything is written into StagingDir(DIR) and replaces DIR in Finish()
// (ReplaceDirectory, common/file_io.h).
#pragma once

#include <Eigen/Core>
#include <map>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "frontend/stereo_frontend.h"
#include "geometry/plucker.h"
#include "methods/pose_tracker.h"

namespace slt {

class FrontEndPictures {
 public:
  // A file every picture directory holds: it marks one as this class's output, which a new run
  // may replace whole (CheckReplaceableDirectory, common/file_io.h).
  static constexpr const char* kMarkerFile = "reprojection_error.csv";
  // `frames`: how many frames the run will have (to place the middle pictures).
  FrontEndPictures(const std::string& dir, const StereoRig& rig, int frames);
  void AddFrame(int k, const cv::Mat& left, const cv::Mat& right, const StereoFrontEnd& front_end,
                const StereoFrame& frame, const TrackerOutput& output);
  void Finish();

  // Mean angle (deg) between the tracked and re-projected reference lines of the last frame,
  // and how many lines it averages (0: none left).
  double last_mean_angle_deg() const { return last_angle_; }
  int last_count() const { return last_count_; }

 private:
  std::string dir_, partial_;
  StereoRig rig_;
  int frames_;
  struct ReferenceLine {
    PlueckerLine line;  // in the world = left camera at the first frame
    // The first pair's left endpoints on the line, in the world (when both are in front).
    std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> ends;
  };
  std::map<std::int64_t, ReferenceLine> reference_;
  struct Point {
    int frame;
    double angle_deg;
    int lines;
  };
  std::vector<Point> curve_;
  double last_angle_ = 0.0;
  int last_count_ = 0;
};

// Draws a y-against-x curve with axes into a PNG (the Fig. 9 style plot).
void WriteCurvePng(const std::string& path, const std::vector<double>& x, const std::vector<double>& y,
                   const std::string& title, const std::string& x_label, const std::string& y_label);

}  // namespace slt
