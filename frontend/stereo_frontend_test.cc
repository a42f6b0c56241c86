#include "frontend/stereo_frontend.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <memory>

#include "frontend/frontend_audit.h"
#include "frontend/line_motion.h"
#include "frontend/rendered_pair.h"

namespace slt {
namespace {

// Frames 0 and 12 of the room loop: about 12 cm and 3.6 deg apart, lines move by tens of
// pixels, beyond the reach of a 2-level pyramid (21 px window).
constexpr int kFar = 12;

struct FarPairResult {
  int tracked = 0, correct = 0, live = 0, predicted = 0;
  // Tracked lines that the stereo pair can place on frame 0 (farther than
  // matching.epipolar_angle_deg from the rows): those the prediction can seed.
  int placeable = 0;
};

// The front end on frame 0 (detection), then on frame kFar with or without the true motion as
// the prediction; tracks judged against the ground-truth lines under them in both frames.
FarPairResult TrackFarPair(const RenderedRoom& room, bool with_prediction) {
  FrontEndOptions options;
  options.tracking.pyramid_levels = 2;
  options.motion.unpredicted_pyramid_levels = 2;
  options.motion.rematch_below_fraction = 0.0;  // the flow alone
  StereoFrontEnd front_end(options, room.rig());
  const StereoFrame first = front_end.Process(room.Image(0, 0), room.Image(0, 1), 0.0, true);
  const Rigid3d cam0_from_world = room.sequence().ground_truth[0].world_from_cam.Inverse();
  const Rigid3d cam_far_from_world = room.sequence().ground_truth[kFar].world_from_cam.Inverse();
  const std::optional<Rigid3d> motion =
      with_prediction ? std::optional<Rigid3d>(cam_far_from_world * cam0_from_world.Inverse()) : std::nullopt;
  const StereoFrame& far = front_end.Process(room.Image(kFar, 0), room.Image(kFar, 1), 1.0, false, motion);
  const ProjectedGroundTruth truth0 = room.Projected(0, 0), truth_far = room.Projected(kFar, 0);
  std::map<std::int64_t, Segment2d> start;
  for (const LineObservation& o : first.left) start[o.id] = o.segment;
  FarPairResult result;
  result.live = static_cast<int>(first.left.size());
  result.tracked = front_end.last_stats().tracked;
  result.predicted = front_end.last_stats().predicted;
  std::vector<int> under0, under_far;
  const StereoGeometry geometry(room.rig());
  const double epipolar_sine = std::sin(options.matching.epipolar_angle_deg * M_PI / 180.0);
  for (const LineObservation& o : far.left) {
    result.placeable += geometry.EpipolarSine(start.at(o.id)) >= epipolar_sine;
    truth0.LinesUnder(start.at(o.id), &under0);
    truth_far.LinesUnder(o.segment, &under_far);
    const bool same = std::any_of(under0.begin(), under0.end(), [&](int line) {
      return std::binary_search(under_far.begin(), under_far.end(), line);
    });
    result.correct += same;
  }
  return result;
}

TEST(StereoFrontEnd, PredictedMotionSeedsTheFlowBeyondThePyramidsReach) {
  const RenderedRoom room;
  const FarPairResult plain = TrackFarPair(room, false);
  const FarPairResult seeded = TrackFarPair(room, true);
  ASSERT_GE(plain.live, 40);
  // Plain LK loses most lines at this motion (or keeps them on the wrong edges) ...
  EXPECT_LT(plain.correct, 0.15 * plain.live) << plain.correct << " of " << plain.live;
  // ... the seeded flow keeps most of them, on their own 3-D lines: the prediction seeds the
  // lines the pair can place (the others, near the rows, move by the scene's median depth).
  ASSERT_GE(seeded.placeable, 15);
  EXPECT_GE(seeded.placeable, 0.5 * seeded.tracked) << seeded.placeable << " of " << seeded.tracked;
  EXPECT_GE(seeded.predicted, 0.9 * seeded.placeable) << seeded.predicted << " of " << seeded.placeable;
  EXPECT_GE(seeded.tracked, 0.4 * seeded.live) << seeded.tracked << " of " << seeded.live;
  EXPECT_GE(seeded.correct, 0.95 * seeded.tracked) << seeded.correct << " of " << seeded.tracked;
}

TEST(StereoFrontEnd, DetectionsOnLiveLinesAreNotMatchedAgainAndTheSnapCanBeOff) {
  const RenderedRoom room;
  FrontEndOptions options;
  StereoFrontEnd front_end(options, room.rig());
  const int first = static_cast<int>(front_end.Process(room.Image(0, 0), room.Image(0, 1), 0.0, true).left.size());
  ASSERT_GE(first, 40);
  const int detected_first = front_end.last_stats().detected_left;
  // The same pair again with detection: the lines are live (tracked by a zero flow), so their
  // detections are dropped before description and matching, and none is added twice.
  front_end.Process(room.Image(0, 0), room.Image(0, 1), 1.0, true);
  EXPECT_GE(front_end.last_stats().tracked, 0.9 * first);
  EXPECT_LT(front_end.last_stats().detected_left, 0.5 * detected_first) << detected_first;
  EXPECT_LT(front_end.last_stats().added, 0.1 * first);
  // With the tracker's snap off (radius 0) the detections are not snapped, nor dropped.
  options.tracking.snap_radius_px = 0.0;
  StereoFrontEnd unsnapped(options, room.rig());
  EXPECT_GE(unsnapped.Process(room.Image(0, 0), room.Image(0, 1), 0.0, true).left.size(), 0.8 * first);
}

TEST(StereoFrontEnd, CountsTheLostLinesByTheStageThatDroppedThem) {
  // The room's first pair, then the same left image with a flat grey right one: every line is
  // lost in the right image, and counted once, under that image's reason (the flow or the snap),
  // not as a stereo failure. On the same pair again the few lines lost are counted as well.
  const RenderedRoom room;
  StereoFrontEnd front_end(FrontEndOptions(), room.rig());
  const int first = static_cast<int>(front_end.Process(room.Image(0, 0), room.Image(0, 1), 0.0, true).left.size());
  ASSERT_GE(first, 40);
  const cv::Mat flat(room.Image(0, 1).size(), CV_8UC1, cv::Scalar(128));
  front_end.Process(room.Image(0, 0), flat, 1.0, false);
  const FrontEndFrameStats& stats = front_end.last_stats();
  EXPECT_EQ(stats.tracked, 0);
  EXPECT_EQ(stats.lost(), first);
  EXPECT_EQ(stats.lost_by[static_cast<int>(LineLoss::kKept)], 0);
  EXPECT_EQ(stats.lost_by[static_cast<int>(LineLoss::kStereo)], 0);
  StereoFrontEnd again(FrontEndOptions(), room.rig());
  const int live = static_cast<int>(again.Process(room.Image(0, 0), room.Image(0, 1), 0.0, true).left.size());
  again.Process(room.Image(0, 0), room.Image(0, 1), 1.0, false);
  EXPECT_EQ(again.last_stats().tracked + again.last_stats().lost(), live);
}

TEST(StereoFrontEnd, NewMatchesAreCheckedAgainstThePreviousPairWithThePredictedMotion) {
  // Paper scene frames 19 and 20, detection on both; the second pair's matches with and
  // without matching.max_previous_px, given the true motion as the prediction.
  const RenderedPaper paper(21);
  const auto second_pair = [&](double max_previous_px, bool with_prediction) {
    FrontEndOptions options;
    options.matching.max_previous_px = max_previous_px;
    auto front_end = std::make_unique<StereoFrontEnd>(options, paper.rig());
    front_end->Process(paper.Image(19, 0), paper.Image(19, 1), 0.0, true);
    const std::optional<Rigid3d> motion =
        with_prediction ? std::optional<Rigid3d>(paper.Motion(19, 20)) : std::nullopt;
    front_end->Process(paper.Image(20, 0), paper.Image(20, 1), 1.0, true, motion);
    return front_end;
  };
  const size_t all = second_pair(0.0, true)->last_matches().size();
  const std::unique_ptr<StereoFrontEnd> on = second_pair(2.0, true);
  const size_t checked = on->last_matches().size();
  // Without a prediction there is nothing to move the lines by: no check.
  EXPECT_EQ(second_pair(2.0, false)->last_matches().size(), second_pair(0.0, false)->last_matches().size());
  ASSERT_GE(all, 10u);
  EXPECT_LT(checked, all);
  EXPECT_GT(checked, 0u);
  // Every kept match passes the check on the previous pair.
  const LineFlowTracker flow(FrontEndOptions().tracking);
  ImagePyramid previous[2];
  for (int c = 0; c < 2; ++c) flow.BuildPyramid(paper.Image(19, c), &previous[c]);
  const cv::Mat derivatives[2] = {previous[0][1], previous[1][1]};
  SnapWorkspace workspace;
  for (const StereoMatch& m : on->last_matches()) {
    EXPECT_TRUE(SeenInPreviousPair(paper.rig(), paper.Motion(20, 19), on->last_detections(0)[m.left].segment,
                                   on->last_detections(1)[m.right].segment, derivatives, FrontEndOptions().tracking, 2.0,
                                   &workspace));
  }
}

TEST(StereoFrontEnd, WithAMeasuredMotionNewLinesAreMatchedInThePreviousPairAndCheckedAgainstTheTwoBefore) {
  // Paper scene frames 16-20 with the true motions as the prediction and the measurement;
  // detection asked on frame 20. With the check on, the matches are made in pair 19 and must
  // lie on edges in pairs 18 and 17 when moved there; the uniqueness tests then weigh only the
  // candidates that pass, so look-alike bars the ratio test gives up on are matched.
  const RenderedPaper paper(21);
  SimulatedSequence judged = paper.sequence();
  judged.lines = WithBarSecondEdges(paper.sequence());
  const auto run = [&](double max_previous_px) {
    // The paper scene's matching options (PaperSceneOptions, frontend_audit.h: its disparity
    // range and row check), its tracking options left at the defaults.
    FrontEndOptions options = FrontEndOptionsFromJson(
        {{"matching", PaperSceneOptions(paper.rig())["matching"]}}, "paper scene matching");
    options.detection.detector = LineDetectorType::kLsd;  // the detections measured below
    options.matching.max_previous_px = max_previous_px;
    options.matching.previous_pairs = 2;
    auto front_end = std::make_unique<StereoFrontEnd>(options, paper.rig());
    for (int k = 16; k <= 20; ++k) {
      const std::optional<Rigid3d> predicted =
          k > 16 ? std::optional<Rigid3d>(paper.Motion(k - 1, k)) : std::nullopt;
      const std::optional<Rigid3d> measured =
          k > 17 ? std::optional<Rigid3d>(paper.Motion(k - 2, k - 1)) : std::nullopt;
      front_end->Process(paper.Image(k, 0), paper.Image(k, 1), k, k == 16 || k == 20, predicted, measured);
    }
    return front_end;
  };
  const auto correct_matches = [&](const StereoFrontEnd& front_end, int frame) {
    const ProjectedGroundTruth left = ProjectedGroundTruthAt(judged, frame, 0), right = ProjectedGroundTruthAt(judged, frame, 1);
    int correct = 0, wrong = 0;
    std::vector<int> common;
    for (const StereoMatch& m : front_end.last_matches()) {
      const PairVerdict verdict = JudgeStereoPair(left, right, front_end.last_detections(0)[m.left].segment,
                                                  front_end.last_detections(1)[m.right].segment, &common);
      correct += verdict == PairVerdict::kCorrect;
      wrong += verdict == PairVerdict::kWrong;
    }
    return std::make_pair(correct, wrong);
  };
  const std::unique_ptr<StereoFrontEnd> off = run(0.0), on = run(1.0);
  EXPECT_EQ(off->last_stats().detection_lag, 0);
  ASSERT_EQ(on->last_stats().detection_lag, 1);
  const auto [correct_off, wrong_off] = correct_matches(*off, 20);
  const auto [correct_on, wrong_on] = correct_matches(*on, 19);
  EXPECT_EQ(wrong_on, 0);
  EXPECT_GT(correct_on, correct_off);
  // Every match passes the check against pairs 18 and 17 with the true motion.
  const LineFlowTracker flow(FrontEndOptions().tracking);
  SnapWorkspace workspace;
  for (const int earlier : {18, 17}) {
    ImagePyramid pyramids[2];
    for (int c = 0; c < 2; ++c) flow.BuildPyramid(paper.Image(earlier, c), &pyramids[c]);
    const cv::Mat derivatives[2] = {pyramids[0][1], pyramids[1][1]};
    for (const StereoMatch& m : on->last_matches()) {
      EXPECT_TRUE(SeenInPreviousPair(paper.rig(), paper.Motion(19, earlier), on->last_detections(0)[m.left].segment,
                                     on->last_detections(1)[m.right].segment, derivatives, FrontEndOptions().tracking,
                                     1.0, &workspace));
    }
  }
  // The new lines were tracked from pair 19 into pair 20 with the live ones.
  EXPECT_GT(on->last_stats().added, 0);
  EXPECT_GE(on->last_stats().live, on->last_stats().added);
}

TEST(LineMotion, PlaneHomographiesMoveTheLinesPointsExactly) {
  // A 3-D line seen by the default rig, the camera moved by a large known motion: the maps
  // send the old images' points of the line onto the new images' line.
  const StereoRig rig;
  const Eigen::Vector3d p(-0.3, 0.2, 2.0), q(0.4, -0.25, 3.0);
  const Rigid3d next_from_previous(Eigen::AngleAxisd(0.1, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix(),
                                   Eigen::Vector3d(0.3, -0.05, -0.4));
  const auto project = [&](const Rigid3d& cam_from_left, const PinholeCamera& camera, const Eigen::Vector3d& x) {
    return camera.Project(cam_from_left * x);
  };
  const Rigid3d identity;
  const auto segment = [&](const Rigid3d& cam_from_left, const PinholeCamera& camera) {
    Segment2d s;
    s << project(cam_from_left, camera, p), project(cam_from_left, camera, q);
    return s;
  };
  StereoLineMaps maps;
  ASSERT_TRUE(PredictStereoLineMotion(rig, next_from_previous, segment(identity, rig.left),
                                      segment(rig.right_from_left, rig.right), 0.01, &maps));
  for (double f : {0.0, 0.3, 1.0}) {
    const Eigen::Vector3d x = p + f * (q - p);
    const Eigen::Vector2d left_now = project(next_from_previous, rig.left, x);
    const Eigen::Vector2d right_now = project(rig.right_from_left * next_from_previous, rig.right, x);
    const Eigen::Vector3d l = maps.left * Homogeneous(project(identity, rig.left, x));
    const Eigen::Vector3d r = maps.right * Homogeneous(project(rig.right_from_left, rig.right, x));
    EXPECT_LT((l.head<2>() / l.z() - left_now).norm(), 1e-6);
    EXPECT_LT((r.head<2>() / r.z() - right_now).norm(), 1e-6);
  }
  // A line in an epipolar plane (parallel to the baseline) has no depth from the pair.
  const Eigen::Vector3d a(-0.3, 0.2, 2.0), b(0.3, 0.2, 2.0);
  Segment2d left_h, right_h;
  left_h << project(identity, rig.left, a), project(identity, rig.left, b);
  right_h << project(rig.right_from_left, rig.right, a), project(rig.right_from_left, rig.right, b);
  EXPECT_FALSE(PredictStereoLineMotion(rig, next_from_previous, left_h, right_h, 0.01, &maps));
}

}  // namespace
}  // namespace slt
