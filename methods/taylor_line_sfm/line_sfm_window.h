// The sliding-window line structure-from-motion problem of the Taylor & Kriegman baseline
// (C.J. Taylor, D.J. Kriegman, IEEE PAMI 17(11), 1995), solved with Ceres.
//
// The window holds the last K stereo frames (their left cameras' cam_from_world T_f) and the
// 3-D lines L_i (world frame) they observe, and minimises Taylor's error over both cameras of
// every frame, the rig's right_from_left E fixed:
//     sum_f sum_{i seen in f} sum_{c in {left, right}} rho(|r(C_c T_f, L_i; segment_fic)|^2),
// C_left = I, C_right = E, r Taylor's segment residual (taylor_segment_cost.h), rho the robust
// loss. The fixed baseline gives metric scale, so two lines seen in two stereo frames already
// over-determine the motion.
//
// Gauge: the oldest frame in the problem is held constant. Which frames and lines enter is
// decided each solve: a line needs observations in min_observation_frames frames of the
// problem, a frame needs at least two such lines (a pose is not determined by one line), and
// only the frames connected to the newest one through shared lines take part (a separate group
// would have its own free gauge); these rules are iterated to a fixed point.
//
// Initialisation: a line is triangulated from the stereo pair of the first frame that sees it
// in both images (geometry/plucker.h StereoPairLine, at that frame's pose); pairs whose
// back-projected planes meet at less than min_plane_angle_deg (lines near an epipolar plane),
// or whose line lies behind a camera at a segment's endpoint, are left out, counted, and tried
// again at the line's next stereo frame.
//
// Outliers (not in Taylor & Kriegman, who fit clean segments): besides the robust loss, the
// segments a solve leaves far from their lines are rejected and the window solved again (Solve).
//
// Known simplification: frames leaving the window are dropped, not marginalised (no prior on
// the remaining poses and lines carries their information). Lines no frame of the window
// observes any more are dropped with them.
#pragma once

#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <cstdint>
#include <deque>
#include <memory>
#include <unordered_map>
#include <vector>

#include "dataset/stereo_sequence.h"
#include "optim/line_sfm_manifolds.h"
#include "methods/taylor_line_sfm/taylor_line_sfm_options.h"
#include "optim/taylor_segment_cost.h"

namespace slt {

// One segment of one image of a frame: the line's id and the segment (px).
struct WindowObservation {
  std::int64_t id = 0;
  Segment2d segment = Segment2d::Zero();
  bool outlier = false;  // rejected by a solve: left out of the window's later solves
};

// What a solve did, for the tracker's status and diagnostics.
struct WindowSolveReport {
  bool solved = false;          // Ceres ran and its solution was finite and usable
  bool newest_in_problem = false;  // the newest frame took part (enough lines, connected)
  int newest_lines = 0;         // lines of the problem observed in the newest frame
  int newest_observations = 0;  // their segments (up to one per image)
  int frames = 0;               // frames in the problem (the fixed one included)
  int lines = 0;                // lines in the problem
  int residuals = 0;
  // Lines the newest frame observes that are in the map but seen in too few frames of the
  // window (for instance lines triangulated one frame ago).
  int newest_lines_too_few_observations = 0;
  int solves = 0;                 // Ceres runs: 2 when segments were rejected after the first
  int rejected_observations = 0;  // segments rejected as outliers after the first run
  int dropped_lines = 0;          // lines dropped with them (to be triangulated again)
  int iterations = 0;  // Levenberg-Marquardt steps, successful or not, over the runs
  double initial_cost = 0.0;
  double final_cost = 0.0;
  ceres::TerminationType termination = ceres::CONVERGENCE;
};

struct TriangulationReport {
  int triangulated = 0;  // new lines added to the map
  // Stereo pairs left out: planes nearly parallel (an epipolar-plane line), no line, or a line
  // behind one of the cameras (the pair has an outlier).
  int degenerate = 0;
};

class LineSfmWindow {
 public:
  explicit LineSfmWindow(const TaylorLineSfmOptions& options);

  // Empties the window for a new sequence with this rig.
  void Reset(const StereoRig& rig);

  // Appends the newest frame, with a first guess of its pose and the observations of its two
  // images (each sorted by id, CollectWindowObservations), then drops the frames beyond the
  // window and the lines no remaining frame observes.
  void AddFrame(const Rigid3d& cam_from_world, std::vector<WindowObservation> left,
                std::vector<WindowObservation> right);

  // Builds and solves the window's problem (see the header comment). On a Ceres failure or a
  // non-finite solution every pose and line keeps its value from before the solve. Then, when
  // outlier_rms_sigma > 0, every segment of the problem whose rms distance to its solved line
  // exceeds outlier_rms_sigma * sigma_px is marked an outlier for good; a line with more such
  // segments than others in the window is dropped (its segments judged again later), and the
  // window is solved once more.
  WindowSolveReport Solve();

  // Triangulates the lines of the newest frame seen in both images (paired by
  // dataset/association.h JoinById) and not in the map yet, at the newest frame's pose.
  TriangulationReport TriangulateNewLines();
  // Lines of the map the newest frame observes (in either image).
  int KnownLinesInNewest();
  // Lines of the map the newest frame observes in both images.
  int KnownLinesInBothImagesOfNewest();
  // Lines of the map the newest frame observes whose every segment there (not rejected) lies
  // within rms_sigma * sigma_px of the line at the newest pose. It judges the lines the last
  // solve left out (seen in too few frames) as well: they are independent evidence of the pose.
  int LinesAgreeingInNewest(double rms_sigma);

  int NumFrames() const { return static_cast<int>(frames_.size()); }
  int NumLines() const { return static_cast<int>(lines_.size()); }
  bool HasLine(std::int64_t id) const { return lines_.count(id) > 0; }
  // age 0 = the newest frame.
  Rigid3d Pose(int age) const;
  void SetNewestPose(const Rigid3d& cam_from_world);
  PlueckerLine Line(std::int64_t id) const;  // world frame, |d| = 1; the id must be in the map

 private:
  struct FrameState {
    double pose[kPoseAmbientSize];
    std::vector<WindowObservation> images[2];  // left, right; each sorted by id
    // Per solve: in the problem, and its lines in the problem.
    bool included = false;
    int eligible_lines = 0;
    int offset = -1;  // of its copy in workspace_
  };
  struct LineState {
    double parameters[kLineAmbientSize];
    int observing_frames = 0;  // per solve: included frames that observe it
    bool eligible = false;
    int offset = -1;  // of its copy in workspace_, -1 when not in the problem
    int kept = 0, rejected = 0;  // per solve: its segments judged inliers and outliers
    int visit = -1;              // ForEachLine's mark
  };
  // A residual block of the last problem: costs_[k] belongs to residuals_[k].
  struct ResidualRef {
    WindowObservation* observation;
    LineState* line;
    int pose_offset;
    double weight;
  };

  // Calls visit(LineState&) once for every line of the map frame f observes with a segment not
  // rejected, in either image.
  template <typename Visit>
  void ForEachLine(const FrameState& f, Visit visit);
  // Decides which frames and lines enter the problem; false when the newest frame cannot.
  bool SelectProblem(WindowSolveReport* report);
  WindowSolveReport SolveOnce();
  // Marks the outliers of the last problem, drops the lines they outvote; returns the count.
  int RejectOutliers(WindowSolveReport* report);
  bool InFrontOfBothCameras(const PlueckerLine& in_left, const Segment2d& left, const Segment2d& right) const;

  TaylorLineSfmOptions options_;
  StereoRig rig_;
  SegmentCamera cameras_[2];  // left, right
  double min_plane_sine_ = 0.0;
  PoseManifold pose_manifold_;
  LineManifold line_manifold_;
  std::unique_ptr<ceres::LossFunction> robust_loss_;  // nullptr for "none"
  ceres::Solver::Options solver_options_;

  std::deque<FrameState> frames_;
  std::unordered_map<std::int64_t, LineState> lines_;
  int visit_ = 0;  // ForEachLine's current mark

  // Reused from solve to solve: residual blocks and losses (the problem does not own them;
  // deques keep their addresses while they grow), and the problem's parameters.
  std::deque<TaylorSegmentCost> costs_;
  std::deque<WeightedSegmentLoss> losses_;
  std::vector<double> workspace_;
  std::vector<ResidualRef> residuals_;
};

// The observations of one image for the window: sorted by id (dataset/association.h
// SortedById, `scratch` for the sorted copy when one is needed), the segments the trackers can
// measure (methods/pose_tracker.h UsableSegment).
void CollectWindowObservations(const std::vector<LineObservation>& image, std::vector<LineObservation>* scratch,
                               std::vector<WindowObservation>* out);

}  // namespace slt
