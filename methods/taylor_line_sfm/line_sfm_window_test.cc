#include "methods/taylor_line_sfm/line_sfm_window.h"

#include <gtest/gtest.h>

#include "geometry/se3.h"
#include "simulator/simulator.h"

namespace slt {
namespace {

SimulatedSequence NoiseFree(int frames, int lines = 30) {
  SimulationConfig config;
  config.seed = 3;
  config.frames = frames;
  config.noise.endpoint_px = 0.0;
  config.scene.paper.lines = lines;
  return Simulate(config);
}

Rigid3d TrueCamFromWorld(const SimulatedSequence& sim, int frame) {
  return sim.ground_truth[frame].world_from_cam.Inverse();
}

std::vector<WindowObservation> Segments(const std::vector<LineObservation>& image) {
  std::vector<LineObservation> scratch;
  std::vector<WindowObservation> out;
  CollectWindowObservations(image, &scratch, &out);
  return out;
}

// Appends `frame` to the window at `cam_from_world`.
void Add(const Rigid3d& cam_from_world, const StereoFrame& frame, LineSfmWindow* window) {
  window->AddFrame(cam_from_world, Segments(frame.left), Segments(frame.right));
}

// Resets `window` on the rig and starts it with frame 0 at the identity, its lines triangulated.
void StartAtFrame0(const SimulatedSequence& sim, LineSfmWindow* window) {
  window->Reset(sim.sequence.rig);
  Add(Rigid3d(), sim.sequence.frames[0], window);
  window->TriangulateNewLines();
}

double RotationErrorDeg(const Rigid3d& a, const Rigid3d& b) {
  return RotationAngle(a.rotation * b.rotation.transpose()) * 180.0 / M_PI;
}

// The angle between two lines' directions and the distance between their moments (|d| = 1).
void ExpectSameLine(const PlueckerLine& a, const PlueckerLine& b, double tolerance) {
  const double sign = a.direction.dot(b.direction) < 0.0 ? -1.0 : 1.0;
  const double scale = 1.0 / a.direction.norm(), other = sign / b.direction.norm();
  EXPECT_LT((a.direction * scale - b.direction * other).norm(), tolerance);
  EXPECT_LT((a.moment * scale - b.moment * other).norm(), tolerance);
}

// The first `frames` frames of `sim`, frame 0 exact (the gauge) with its lines triangulated,
// the others off by about 1 deg and 1 cm.
void FillPerturbed(const SimulatedSequence& sim, int frames, LineSfmWindow* window) {
  window->Reset(sim.sequence.rig);
  for (int k = 0; k < frames; ++k) {
    const Vector6d error = k == 0 ? Vector6d::Zero() : (Vector6d() << 0.01, -0.01, 0.01, 0.02, -0.01, 0.015).finished();
    Add(ExpSE3(error) * TrueCamFromWorld(sim, k), sim.sequence.frames[k], window);
    if (k == 0) window->TriangulateNewLines();
  }
}

TEST(CollectWindowObservations, SortsByIdAndDropsWhatCannotBeUsed) {
  const std::vector<LineObservation> image = {{7, Segment2d(0, 0, 100, 0)},  {3, Segment2d(0, 0, 0, 50)},
                                              {5, Segment2d(0, 0, 4.9, 0)},  // too short
                                              {9, Segment2d(0, 0, 50, 50)},  {9, Segment2d(1, 1, 60, 60)},
                                              {4, Segment2d(0, NAN, 50, 50)}, {6, Segment2d(0, INFINITY, 50, 50)}};
  const std::vector<WindowObservation> out = Segments(image);
  // An id listed twice stays twice, in order: the association step (dataset/association.h)
  // pairs such runs element by element.
  const std::vector<std::int64_t> expected = {3, 7, 9, 9};
  ASSERT_EQ(out.size(), expected.size());
  for (size_t i = 0; i < out.size(); ++i) EXPECT_EQ(out[i].id, expected[i]) << i;
  EXPECT_EQ(out[0].segment, Segment2d(0, 0, 0, 50));
  EXPECT_EQ(out[3].segment, Segment2d(1, 1, 60, 60));
  EXPECT_FALSE(out[0].outlier);
}

TEST(LineSfmWindow, TriangulatesNoiseFreeStereoPairsExactly) {
  const SimulatedSequence sim = NoiseFree(2);
  LineSfmWindow window{TaylorLineSfmOptions()};
  window.Reset(sim.sequence.rig);
  // At a pose other than the identity: the line is mapped to the world with it.
  Add(TrueCamFromWorld(sim, 1), sim.sequence.frames[1], &window);
  const TriangulationReport report = window.TriangulateNewLines();
  EXPECT_GT(report.triangulated, 20);
  int stereo_pairs = 0;
  for (const LineObservation& l : sim.sequence.frames[1].left) {
    for (const LineObservation& r : sim.sequence.frames[1].right) stereo_pairs += l.id == r.id;
  }
  EXPECT_EQ(report.triangulated + report.degenerate, stereo_pairs);
  ASSERT_EQ(window.NumLines(), report.triangulated);
  for (size_t id = 0; id < sim.lines.size(); ++id) {
    if (!window.HasLine(id)) continue;
    const Line3d& truth = sim.lines[id];
    ExpectSameLine(window.Line(id), {truth.p.cross(truth.q - truth.p), truth.q - truth.p}, 1e-9);
  }
  // Triangulating again adds nothing: every line is known.
  EXPECT_EQ(window.TriangulateNewLines().triangulated, 0);
}

TEST(LineSfmWindow, LeavesOutLinesInTheEpipolarPlane) {
  // A line in the plane y = 0, which holds both camera centres, lies in an epipolar plane of the
  // x-baseline rig: its two back-projected planes coincide. A line crossing it steeply passes
  // (planes about 5 deg apart at 1 m).
  const StereoRig rig;
  LineSfmWindow window{TaylorLineSfmOptions()};
  window.Reset(rig);
  auto observe = [&](std::int64_t id, const Eigen::Vector3d& p, const Eigen::Vector3d& q, StereoFrame* frame) {
    const Rigid3d& e = rig.right_from_left;
    frame->left.push_back({id, (Segment2d() << rig.left.Project(p), rig.left.Project(q)).finished()});
    frame->right.push_back({id, (Segment2d() << rig.right.Project(e * p), rig.right.Project(e * q)).finished()});
  };
  StereoFrame frame;
  observe(1, {-0.3, 0.0, 1.0}, {0.3, 0.0, 1.2}, &frame);   // in the plane y = 0 through both centres
  observe(2, {-0.1, -0.3, 1.0}, {0.1, 0.3, 1.0}, &frame);  // crosses it
  Add(Rigid3d(), frame, &window);
  const TriangulationReport report = window.TriangulateNewLines();
  EXPECT_EQ(report.degenerate, 1);
  EXPECT_EQ(report.triangulated, 1);
  EXPECT_FALSE(window.HasLine(1));
  EXPECT_TRUE(window.HasLine(2));
}

TEST(LineSfmWindow, LeavesOutALineBehindTheCameras) {
  // A vertical line 1 m ahead; in the right image it is moved to the right of its left image,
  // a negative disparity: the back-projected planes meet behind the cameras.
  const StereoRig rig;
  LineSfmWindow window{TaylorLineSfmOptions()};
  window.Reset(rig);
  const Eigen::Vector3d p(0.05, -0.2, 1.0), q(0.05, 0.2, 1.0);
  StereoFrame frame;
  frame.left.push_back({1, (Segment2d() << rig.left.Project(p), rig.left.Project(q)).finished()});
  frame.right.push_back({1, frame.left[0].segment + Segment2d(30, 0, 30, 0)});
  Add(Rigid3d(), frame, &window);
  const TriangulationReport report = window.TriangulateNewLines();
  EXPECT_EQ(report.degenerate, 1);
  EXPECT_FALSE(window.HasLine(1));
  // With the true disparity (f b / z = 84.9 px to the left) it is triangulated.
  frame.right[0].segment = frame.left[0].segment - Segment2d(rig.right.fx * 0.1, 0, rig.right.fx * 0.1, 0);
  Add(Rigid3d(), frame, &window);
  EXPECT_EQ(window.TriangulateNewLines().triangulated, 1);
}

TEST(LineSfmWindow, SolveRecoversThePosesFromAPerturbedStartWithTheOldestFixed) {
  const SimulatedSequence sim = NoiseFree(5);
  LineSfmWindow window{TaylorLineSfmOptions()};
  FillPerturbed(sim, 5, &window);
  const WindowSolveReport report = window.Solve();
  ASSERT_TRUE(report.solved);
  EXPECT_TRUE(report.newest_in_problem);
  EXPECT_EQ(report.frames, 5);
  EXPECT_GT(report.newest_lines, 20);
  EXPECT_EQ(report.newest_lines_too_few_observations, 0);
  EXPECT_LT(report.final_cost, 1e-12 * report.initial_cost);
  EXPECT_GE(report.iterations, 2);
  EXPECT_LE(report.iterations, TaylorLineSfmOptions().max_iterations);
  for (int k = 0; k < 5; ++k) {
    const Rigid3d estimate = window.Pose(4 - k), truth = TrueCamFromWorld(sim, k);
    EXPECT_LT(RotationErrorDeg(estimate, truth), 1e-7) << "frame " << k;
    EXPECT_LT((estimate.translation - truth.translation).norm(), 1e-9) << "frame " << k;
  }
  EXPECT_EQ(window.Pose(4).ToMatrix4(), TrueCamFromWorld(sim, 0).ToMatrix4());  // held fixed, bit for bit
}

// Solves the five frames of `sim` (one segment of line `id` spoilt) from a perturbed start and
// expects that one segment rejected, the line kept, and the newest pose exact again.
void ExpectOneSegmentRejected(const SimulatedSequence& sim, std::int64_t id, LineSfmWindow* window) {
  FillPerturbed(sim, 5, window);
  const WindowSolveReport report = window->Solve();
  ASSERT_TRUE(report.solved);
  EXPECT_EQ(report.solves, 2);
  EXPECT_EQ(report.rejected_observations, 1);
  EXPECT_EQ(report.dropped_lines, 0);
  EXPECT_TRUE(window->HasLine(id));
  const Rigid3d truth = TrueCamFromWorld(sim, 4);
  EXPECT_LT(RotationErrorDeg(window->Pose(0), truth), 1e-7);
  EXPECT_LT((window->Pose(0).translation - truth.translation).norm(), 1e-9);
}

TEST(LineSfmWindow, RejectsAnOutlierSegmentAndSolvesAgain) {
  SimulatedSequence sim = NoiseFree(5);
  // One segment of the newest frame replaced by an unrelated one under the same id.
  StereoFrame& newest = sim.sequence.frames[4];
  newest.left[3].segment << 50, 400, 300, 100;
  LineSfmWindow window{TaylorLineSfmOptions()};
  ExpectOneSegmentRejected(sim, newest.left[3].id, &window);
  // The rejected segment stays out of later solves.
  EXPECT_EQ(window.Solve().rejected_observations, 0);
}

TEST(LineSfmWindow, AWrongStereoPairLosesItsSegmentNotItsLine) {
  // Frame 0 triangulates line `id` with its right segment moved by 20 px (a wrong depth);
  // frames 1-4 see it where it is. The robust solve moves the line to its eight good segments
  // and rejects the bad one.
  SimulatedSequence sim = NoiseFree(5);
  StereoFrame& first = sim.sequence.frames[0];
  first.right[2].segment += Segment2d(-20, 0, -20, 0);
  LineSfmWindow window{TaylorLineSfmOptions()};
  ExpectOneSegmentRejected(sim, first.right[2].id, &window);
}

TEST(LineSfmWindow, ALineMostOfWhoseSegmentsAreRejectedIsDroppedAndItsSegmentsJudgedAgain) {
  // A threshold no residual meets rejects every segment: every line of the problem is outvoted
  // and dropped, the second run has nothing left, and triangulating the newest frame brings the
  // lines back with their segments usable again.
  const SimulatedSequence sim = NoiseFree(3);
  TaylorLineSfmOptions options;
  options.outlier_rms_sigma = 1e-150;  // squared, still above 0
  LineSfmWindow window(options);
  FillPerturbed(sim, 3, &window);
  const int lines = window.NumLines();
  const WindowSolveReport report = window.Solve();
  EXPECT_EQ(report.dropped_lines, lines);
  EXPECT_EQ(window.NumLines(), 0);
  EXPECT_FALSE(report.solved);  // the second run: no lines
  EXPECT_EQ(window.TriangulateNewLines().triangulated, lines);
  Add(TrueCamFromWorld(sim, 2), sim.sequence.frames[2], &window);
  // The next solve uses the segments of frames 0 and 1 again (their rejections were cleared
  // with the lines), and rejects them again; only segments that fit exactly escape (frame 2 seen
  // twice at one pose).
  int old_segments = 0;
  for (int k : {0, 1}) {
    for (const std::vector<LineObservation>* image : {&sim.sequence.frames[k].left, &sim.sequence.frames[k].right}) {
      for (const WindowObservation& o : Segments(*image)) old_segments += window.HasLine(o.id);
    }
  }
  const WindowSolveReport again = window.Solve();
  EXPECT_GT(again.rejected_observations, old_segments);
  EXPECT_EQ(again.dropped_lines, lines);
}

TEST(LineSfmWindow, ASolveStoppedByTheIterationLimitIsStillUsed) {
  const SimulatedSequence sim = NoiseFree(3);
  TaylorLineSfmOptions options;
  options.max_iterations = 1;
  LineSfmWindow window(options);
  FillPerturbed(sim, 3, &window);
  const WindowSolveReport report = window.Solve();
  EXPECT_EQ(report.iterations, 1);
  EXPECT_EQ(report.termination, ceres::NO_CONVERGENCE);
  EXPECT_TRUE(report.solved);
  EXPECT_LT(report.final_cost, report.initial_cost);
}

TEST(LineSfmWindow, KeepsTheLastKFramesAndTheLinesTheyObserve) {
  const SimulatedSequence sim = NoiseFree(4);
  TaylorLineSfmOptions options;
  options.window_frames = 2;
  LineSfmWindow window(options);
  StartAtFrame0(sim, &window);
  const int lines = window.NumLines();
  ASSERT_GT(lines, 2);
  // Frame 1 observes only two of the lines: the others leave with frame 0 when frame 2 comes.
  StereoFrame sparse = sim.sequence.frames[1];
  sparse.left.resize(2);
  sparse.right.clear();
  for (const LineObservation& o : sim.sequence.frames[1].right) {
    if (o.id == sparse.left[0].id || o.id == sparse.left[1].id) sparse.right.push_back(o);
  }
  Add(TrueCamFromWorld(sim, 1), sparse, &window);
  EXPECT_EQ(window.NumFrames(), 2);
  EXPECT_EQ(window.NumLines(), lines);
  window.AddFrame(TrueCamFromWorld(sim, 2), {}, {});
  EXPECT_EQ(window.NumFrames(), 2);
  EXPECT_EQ(window.NumLines(), 2);
  EXPECT_TRUE(window.HasLine(sparse.left[0].id));
}

TEST(LineSfmWindow, AFrameWithOneLineIsNotSolved) {
  const SimulatedSequence sim = NoiseFree(2);
  LineSfmWindow window{TaylorLineSfmOptions()};
  StartAtFrame0(sim, &window);
  StereoFrame one = sim.sequence.frames[1];
  one.left.resize(1);
  one.right.clear();
  const Rigid3d guess = TrueCamFromWorld(sim, 1);
  Add(guess, one, &window);
  const WindowSolveReport report = window.Solve();
  EXPECT_FALSE(report.newest_in_problem);
  EXPECT_FALSE(report.solved);
  EXPECT_EQ(window.Pose(0).ToMatrix4(), guess.ToMatrix4());
}

TEST(LineSfmWindow, CountsTheLinesWhoseNewestSegmentsFitThemAtTheNewestPose) {
  const SimulatedSequence sim = NoiseFree(2);
  LineSfmWindow window{TaylorLineSfmOptions()};
  StartAtFrame0(sim, &window);
  // Frame 1 at its true pose, but the left segment of its first line moved 20 px across.
  StereoFrame moved = sim.sequence.frames[1];
  ASSERT_FALSE(moved.left.empty());
  Segment2d& s = moved.left[0].segment;
  const Eigen::Vector2d normal = Eigen::Vector2d(s(1) - s(3), s(2) - s(0)).normalized();
  s += 20.0 * (Segment2d() << normal, normal).finished();
  Add(TrueCamFromWorld(sim, 1), moved, &window);
  const int known = window.KnownLinesInNewest();
  ASSERT_GT(known, 10);
  // Noise-free segments at the true pose lie on their lines (well within 1 sigma); the moved
  // one is about 20 px / 1.5 px = 13 sigma away, so its line no longer agrees below that.
  EXPECT_EQ(window.LinesAgreeingInNewest(1.0), known - 1);
  EXPECT_EQ(window.LinesAgreeingInNewest(20.0), known);
  // A wrong pose (5 cm sideways) leaves no line agreeing within 1 sigma.
  window.SetNewestPose(ExpSE3((Vector6d() << 0.05, 0, 0, 0, 0, 0).finished()) * TrueCamFromWorld(sim, 1));
  EXPECT_EQ(window.LinesAgreeingInNewest(1.0), 0);
}

TEST(LineSfmWindow, LinesTriangulatedInTheNewestFrameWaitForASecondFrame) {
  const SimulatedSequence sim = NoiseFree(3);
  LineSfmWindow window{TaylorLineSfmOptions()};
  window.Reset(sim.sequence.rig);
  // Frame 0 sees only lines with even ids; frame 1 all of them.
  StereoFrame even = sim.sequence.frames[0];
  auto odd = [](const LineObservation& o) { return o.id % 2 == 1; };
  even.left.erase(std::remove_if(even.left.begin(), even.left.end(), odd), even.left.end());
  even.right.erase(std::remove_if(even.right.begin(), even.right.end(), odd), even.right.end());
  Add(Rigid3d(), even, &window);
  window.TriangulateNewLines();
  Add(TrueCamFromWorld(sim, 1), sim.sequence.frames[1], &window);
  window.TriangulateNewLines();  // the odd lines, seen once so far
  Add(TrueCamFromWorld(sim, 2), sim.sequence.frames[2], &window);
  const WindowSolveReport report = window.Solve();
  ASSERT_TRUE(report.solved);
  // Every line is now seen in two frames or more.
  EXPECT_EQ(report.newest_lines_too_few_observations, 0);

  TaylorLineSfmOptions strict;
  strict.min_observation_frames = 3;
  LineSfmWindow window3(strict);
  window3.Reset(sim.sequence.rig);
  Add(Rigid3d(), even, &window3);
  window3.TriangulateNewLines();
  Add(TrueCamFromWorld(sim, 1), sim.sequence.frames[1], &window3);
  window3.TriangulateNewLines();
  Add(TrueCamFromWorld(sim, 2), sim.sequence.frames[2], &window3);
  const WindowSolveReport report3 = window3.Solve();
  ASSERT_TRUE(report3.solved);
  // The odd lines (triangulated at frame 1) are seen in two frames only; the even ones in three.
  const int known = window3.KnownLinesInNewest();
  int odd_known = 0;
  for (std::int64_t id = 1; id < static_cast<std::int64_t>(sim.lines.size()); id += 2) {
    const auto seen = [id](const std::vector<LineObservation>& image) {
      return std::any_of(image.begin(), image.end(), [id](const LineObservation& o) { return o.id == id; });
    };
    odd_known += window3.HasLine(id) && (seen(sim.sequence.frames[2].left) || seen(sim.sequence.frames[2].right));
  }
  EXPECT_GT(odd_known, 0);
  EXPECT_EQ(report3.newest_lines_too_few_observations, odd_known);
  EXPECT_EQ(report3.newest_lines + odd_known, known);
}

}  // namespace
}  // namespace slt
