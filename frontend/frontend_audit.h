// Measuring the front end against the ground truth of a rendered sequence (docs/frontend.md):
// which ground-truth 3-D segment an image segment lies on, detection recall and precision,
// stereo-match and track correctness, endpoint errors. Used by measure_frontend, the front
// end's end-to-end test and its benchmark; not by the front end itself.
//
// A segment lies on ground-truth segment L (in one camera at one frame) when L, clipped at the
// near plane and projected with the true pose and rig, is a segment P with
//   the angle between the segment and P <= max_angle_deg,
//   both endpoints within max_distance_px of P's line, and
//   the segment overlapping P (their extents along P's line intersect).
// A stereo match is correct when its two segments lie on a common L, wrong when they lie on no
// common L but at least one lies on some L, and not judged when neither lies on any (a line of
// a texture or of a surface's shading that the ground truth does not list: whether its two
// segments are the same line cannot be told). A track is judged when its first pair lies on a
// common L, and then correct when one L is under both its segments in every frame of its life.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "dataset/stereo_sequence.h"
#include "frontend/stereo_frontend.h"
#include "simulator/simulator.h"

namespace slt {

struct AuditCriteria {
  double max_distance_px = 2.0;
  double max_angle_deg = 2.0;
};

// The scene's 3-D segments projected into one camera at one pose.
class ProjectedGroundTruth {
 public:
  ProjectedGroundTruth(const std::vector<Line3d>& lines_in_world, const AuditCriteria& criteria = {});
  // cam_from_world of the camera; the camera's intrinsics and image size (for the near plane
  // only: projections are not clipped to the image).
  void Project(const Rigid3d& cam_from_world, const PinholeCamera& camera, double min_depth_m = 0.05);
  // Indices of the lines under `segment`, ascending.
  void LinesUnder(const Segment2d& segment, std::vector<int>* lines) const;
  // The perpendicular distances of the segment's endpoints to line `index`'s projection.
  Eigen::Vector2d EndpointDistances(const Segment2d& segment, int index) const;

 private:
  struct Projected {
    bool visible = false;
    Eigen::Vector2d a, dir, normal;
    double length = 0.0;
  };
  std::vector<Line3d> lines_;
  AuditCriteria criteria_;
  double cos_max_;
  std::vector<Projected> projected_;
};

// The ground truth of a simulated sequence projected into `camera` (0 = left, 1 = right) at
// `frame`, with the rig the images were made with.
ProjectedGroundTruth ProjectedGroundTruthAt(const SimulatedSequence& sequence, int frame, int camera,
                                            const AuditCriteria& criteria = {});

// Simulation configs of the rendered sequences the front end is measured on (measure_frontend,
// frontend_benchmark, tests): the visible ground truth (clipped, occlusion on), noise-free.
//   room:     the room loop (motion.loop defaults), at 752 x 480 with EuRoC's rectified focal
//             length and 0.11 m baseline when `euroc_size`, else the default 640 x 480 rig;
//   corridor: the corridor walked forward 1 cm per frame, 640 x 480;
//   paper:    the paper's scene and motion (Sec. 5.1: random segments, per-frame motion up to
//             1 cm and 1 deg), 640 x 480, rendered (frontend/configs/paper_640x480.json).
nlohmann::json RenderedRoomConfig(int frames, bool euroc_size);
nlohmann::json RenderedCorridorConfig(int frames);
nlohmann::json RenderedPaperConfig(int frames);

// The paper scene's front-end options (a JSON merge patch over the defaults, for `rig`: the
// rendered paper scene's). Its bars float 0.26-0.70 m from the camera over the 200
// frames (the ground truth's visible segments); with a margin, 0.2-1.0 m is the disparity range
// fx b / z of the rig, given to the matcher as a stereo matcher is given its range (OpenCV's
// minDisparity, numDisparities). Its bars look alike (MSLD and NCC do not tell them apart):
// the matches are verified by their row extents and by the three pairs before (with the
// tracker's measured motion). Its edges are sharp (sub-pixel residuals of 0.05-0.1 px) and
// cross each other: a tracked edge keeps only the edge points within 0.3 px of its line (not
// those of a crossing bar's edge) and grows back along its edge (docs/frontend.md).
nlohmann::json PaperSceneOptions(const StereoRig& rig);

// The scene's lines for judging a front end. On the paper scene each segment is one long edge of
// a bar 4 mm wide (simulator/scene.cc): the images show its second long edge too, which the
// simulator does not list. The lines of `sequence` followed by the edge opposite each listed
// line on its bar (a two-sided four-sided surface with the line as an edge); other scenes'
// lines as they are.
std::vector<Line3d> WithBarSecondEdges(const SimulatedSequence& sequence);

// The front end's output `observed` with its across-line error replaced by a chosen one: each
// line whose track lies on one line L of `lines` in both images in every frame of its life (the
// audit's test, AuditCriteria) is moved onto L's projection (each endpoint along L's normal, so
// its position along the line is kept) and displaced across it by sigma_px N(0, 1), independent
// per endpoint, image and frame (the "frontend_error_model" stream of `seed`); other lines are
// kept as measured. The same lines, ids (tracks) and frames as the run: only the error model
// differs (docs/frontend.md, "the paper scene's ATE").
StereoSequence WithErrorReplaced(const SimulatedSequence& sequence, const std::vector<Line3d>& lines,
                                 const StereoSequence& observed, double sigma_px, std::uint64_t seed,
                                 const AuditCriteria& criteria = {});

// The verdict on a stereo pair of segments (see above); `common` receives the ground-truth
// lines under both, ascending.
enum class PairVerdict { kCorrect, kWrong, kUnjudged };
PairVerdict JudgeStereoPair(const ProjectedGroundTruth& left_truth, const ProjectedGroundTruth& right_truth,
                            const Segment2d& left, const Segment2d& right, std::vector<int>* common);

struct DetectionScore {
  int images = 0;
  int gt_segments = 0;      // visible ground-truth segments at least min_gt_length_px long
  int gt_found = 0;         // ... with a detection lying on them
  int detections = 0;       // detected segments (after merge, length and contrast filters)
  int detections_on_gt = 0; // ... lying on some ground-truth segment
  double endpoint_sq_sum = 0.0;  // perpendicular endpoint distances of detections on the found segments
  int endpoints = 0;
  double seconds = 0.0;
  double Recall() const { return gt_segments ? static_cast<double>(gt_found) / gt_segments : 0.0; }
  double Precision() const { return detections ? static_cast<double>(detections_on_gt) / detections : 0.0; }
  double EndpointRms() const { return endpoints ? std::sqrt(endpoint_sq_sum / endpoints) : 0.0; }
};

// Photometric visibility of the ground truth (docs/frontend.md, "Which segments are visible").
// The simulator's visible segments are geometric: in view and not occluded. An edge between two
// surfaces of nearly the same grey level is geometrically visible but not in the image. The
// step across a segment is measured on the *noise-free* image (the same rendering without
// sensor noise: exposure, vignetting and defocus blur applied) as the median over places every
// 2 px along it (3 px clear of its ends) of |I(x + 2n) - I(x - 2n)| (bilinear), with n its unit
// normal: at least half its length has that step. The segment is photometrically visible when
//   step >= min_noise_multiples * sqrt(2) * sigma(level),
// sigma(level) = sqrt(read_noise^2 + shot_noise * level) the image noise at the mean grey level
// of the two sides (render/image_formation.h), sqrt(2) sigma the noise of the difference of two
// pixels: with min_noise_multiples 1, the step is above the noise of the difference it is
// measured by. A segment without any step (0) is never visible, also without image noise.
struct EdgeStep {
  double step = 0.0;   // median |I(x + 2n) - I(x - 2n)|, grey levels
  double level = 0.0;  // mean of I(x + 2n) and I(x - 2n), grey levels
};
EdgeStep MeasureEdgeStep(const cv::Mat& noise_free_grey, const Segment2d& segment);
// The segments of `visible` that are photometrically visible in `noise_free_grey` (above).
std::vector<LineObservation> PhotometricallyVisible(const std::vector<LineObservation>& visible,
                                                    const cv::Mat& noise_free_grey, const ImageConfig& images,
                                                    double min_noise_multiples = 1.0);

// Scores one image's detections against its visible ground truth (`visible`: the noise-free,
// clipped and occlusion-aware observations of the simulator; ids index the lines of
// `projected`).
void ScoreDetections(const ProjectedGroundTruth& projected, const std::vector<LineObservation>& visible,
                     const std::vector<ImageLine>& detections, double min_gt_length_px, DetectionScore* score);

// Follows a front-end run frame by frame.
class FrontEndAudit {
 public:
  FrontEndAudit(const SimulatedSequence& sequence, const AuditCriteria& criteria = {});
  // After front_end.Process() of frame k returned `frame`.
  void AddFrame(int k, const StereoFrontEnd& front_end, const StereoFrame& frame);
  // Closes the tracks still alive.
  void Finish();

  struct Result {
    int matches = 0, matches_correct = 0;   // every stereo match of the detection frames
    int matches_unjudged = 0;               // ... on no ground-truth line in either image
    int added = 0, added_correct = 0;       // the new lines among them (what the tracker gets)
    int tracks = 0, tracks_correct = 0;     // judged lines followed over >= 2 frames, at their end
    int tracks_unjudged = 0;                // lines followed over >= 2 frames, not judged
    double MatchPrecision() const {
      const int judged = matches - matches_unjudged;
      return judged > 0 ? static_cast<double>(matches_correct) / judged : 0.0;
    }
    double TrackPrecision() const { return tracks > 0 ? static_cast<double>(tracks_correct) / tracks : 0.0; }
    long track_frames = 0;                  // line-frames of those tracks
    int longest_track = 0;                  // frames
    double endpoint_sq_sum = 0.0;           // perpendicular endpoint distances of output lines on the truth
    long endpoints = 0;
    double EndpointRms() const { return endpoints ? std::sqrt(endpoint_sq_sum / endpoints) : 0.0; }
  };
  const Result& result() const { return result_; }

 private:
  void CloseTrack(std::int64_t id);
  const SimulatedSequence& sequence_;
  AuditCriteria criteria_;
  ProjectedGroundTruth projected_[2];
  struct Track {
    std::vector<int> lines;  // ground-truth lines under the track so far (intersection)
    int frames = 0;
    bool seen = false;
    bool judged = false;
  };
  std::map<std::int64_t, Track> tracks_;
  Result result_;
  std::vector<int> common_;
};

}  // namespace slt
