#include "frontend/stereo_matching.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "frontend/frontend_audit.h"
#include "frontend/rendered_pair.h"

namespace slt {
namespace {

const RenderedRoom& Room() {
  static const RenderedRoom room;
  return room;
}

// Detect, describe and match a frame of a rendered sequence (the room by default).
struct MatchedPair {
  std::vector<ImageLine> lines[2];
  std::vector<StereoMatch> matches;
};

MatchedPair MatchFrame(int frame, const FrontEndOptions& options, const RenderedSequence& room = Room(),
                       const StereoMatcher::PairCheck* verify = nullptr) {
  MatchedPair out;
  std::vector<MsldDescriptor> descriptors[2];
  cv::Mat images[2];
  const std::unique_ptr<LineDetector> detector = MakeLineDetector(options.detection);
  MsldExtractor msld;
  for (int c = 0; c < 2; ++c) {
    images[c] = room.Image(frame, c);
    out.lines[c] = DetectLines(*detector, options.detection, images[c]);
    msld.SetImage(images[c]);
    descriptors[c].resize(out.lines[c].size());
    for (size_t i = 0; i < out.lines[c].size(); ++i) msld.Compute(out.lines[c][i].segment, &descriptors[c][i]);
  }
  StereoMatcher matcher(options.matching, room.rig());
  matcher.Match(images[0], images[1], out.lines[0], descriptors[0], out.lines[1], descriptors[1], &out.matches, verify);
  return out;
}

TEST(StereoMatching, RenderedRoomPairMatchesAreCorrectAndOneToOne) {
  const MatchedPair pair = MatchFrame(0, FrontEndOptions());
  const ProjectedGroundTruth truth[2] = {Room().Projected(0, 0), Room().Projected(0, 1)};
  // Identity alone (the same 3-D segment): the looser criteria of measure_frontend.
  const AuditCriteria identity{3.0, 5.0};
  const ProjectedGroundTruth loose[2] = {ProjectedGroundTruthAt(Room().sequence(), 0, 0, identity),
                                         ProjectedGroundTruthAt(Room().sequence(), 0, 1, identity)};
  int correct = 0, same_line = 0, unjudged = 0;
  std::vector<char> used_left(pair.lines[0].size(), 0), used_right(pair.lines[1].size(), 0);
  std::vector<int> common;
  for (const StereoMatch& m : pair.matches) {
    EXPECT_FALSE(used_left[m.left]++) << "left line " << m.left << " matched twice";
    EXPECT_FALSE(used_right[m.right]++) << "right line " << m.right << " matched twice";
    EXPECT_GT(m.ncc, 0.6f);
    const Segment2d& l = pair.lines[0][m.left].segment;
    const Segment2d& r = pair.lines[1][m.right].segment;
    const PairVerdict verdict = JudgeStereoPair(truth[0], truth[1], l, r, &common);
    correct += verdict == PairVerdict::kCorrect;
    unjudged += verdict == PairVerdict::kUnjudged;
    same_line += JudgeStereoPair(loose[0], loose[1], l, r, &common) == PairVerdict::kCorrect;
  }
  // Matches of lines the ground truth does not list (texture, shading) cannot be judged; they
  // are few.
  EXPECT_LE(unjudged, 0.1 * pair.matches.size());
  // Issue 18 asks for >= 99 % correct stereo matches; the room's frame 0 gives enough matches
  // for that to mean something.
  ASSERT_GE(pair.matches.size(), 40u) << "detected " << pair.lines[0].size() << " / " << pair.lines[1].size();
  const double judged = pair.matches.size() - unjudged;
  EXPECT_GE(same_line, 0.99 * judged) << same_line << " of " << judged;
  // Within detection's 2 px and 2 deg in both images (measured: 64 of 64 judged with LSD, 65 of 66 with EDLines).
  EXPECT_GE(correct, 0.95 * judged) << correct << " of " << judged;
}

TEST(StereoMatching, EveryMatchSatisfiesTheGeometry) {
  const MatchingOptions options;
  const MatchedPair pair = MatchFrame(1, FrontEndOptions());
  const StereoGeometry geometry(Room().rig());
  ASSERT_TRUE(geometry.rectified());
  const double sine = std::sin(options.epipolar_angle_deg * M_PI / 180.0);
  for (const StereoMatch& m : pair.matches) {
    const Segment2d& l = pair.lines[0][m.left].segment;
    const Segment2d& r = pair.lines[1][m.right].segment;
    EXPECT_GE(geometry.BeamOverlap(l, r, sine, options.epipolar_distance_px), options.min_overlap);
    EXPECT_TRUE(geometry.DisparityInRange(l, r, options.min_disparity_px, options.max_disparity_px));
    EXPECT_GT((l.tail<2>() - l.head<2>()).dot(r.tail<2>() - r.head<2>()), 0.0) << "orientations differ";
  }
}

TEST(StereoMatching, UnionOverlapVerifiesTheChosenPair) {
  // On the paper scene some matches cover different rows in the two images (an end occluded or
  // clipped, or two different bars); with matching.min_union_overlap those are dropped, the
  // rest kept.
  const RenderedPaper paper(21);
  FrontEndOptions options;
  const MatchedPair all = MatchFrame(20, options, paper);
  options.matching.min_union_overlap = 0.6;
  const MatchedPair verified = MatchFrame(20, options, paper);
  const StereoGeometry geometry(paper.rig());
  const double sine = std::sin(options.matching.epipolar_angle_deg * M_PI / 180.0);
  const auto union_overlap = [&](const MatchedPair& pair, const StereoMatch& m) {
    return geometry.BeamOverlap(pair.lines[0][m.left].segment, pair.lines[1][m.right].segment, sine,
                                options.matching.epipolar_distance_px, StereoGeometry::OverlapOf::kUnion);
  };
  int below = 0;
  for (const StereoMatch& m : all.matches) below += union_overlap(all, m) < 0.6;
  ASSERT_GT(below, 0) << "the test needs matches below the bound";
  EXPECT_EQ(verified.matches.size(), all.matches.size() - below);
  for (const StereoMatch& m : verified.matches) EXPECT_GE(union_overlap(verified, m), 0.6);
}

TEST(StereoMatching, AVerificationIsWeighedBeforeTheUniquenessTests) {
  // Paper scene, frame 20: the look-alike bars fail the ratio test against each other. With a
  // verification that passes exactly the pairs on one ground-truth line (an oracle), the ratio
  // test weighs only those: every match is correct and more bars are matched than the plain
  // matcher's correct matches; a verification that passes nothing leaves no match.
  const RenderedPaper paper(21);
  FrontEndOptions options;
  options.detection.detector = LineDetectorType::kLsd;  // the detections measured below
  const ProjectedGroundTruth truth[2] = {paper.Projected(20, 0), paper.Projected(20, 1)};
  const MatchedPair plain = MatchFrame(20, options, paper);
  std::vector<int> common;
  const auto correct = [&](const Segment2d& l, const Segment2d& r) {
    return JudgeStereoPair(truth[0], truth[1], l, r, &common) == PairVerdict::kCorrect;
  };
  int plain_correct = 0;
  for (const StereoMatch& m : plain.matches) plain_correct += correct(plain.lines[0][m.left].segment, plain.lines[1][m.right].segment);
  // The detections are the same in every run (deterministic), so the check can index them.
  const StereoMatcher::PairCheck oracle = [&](int l, int r) {
    return correct(plain.lines[0][l].segment, plain.lines[1][r].segment);
  };
  const MatchedPair verified = MatchFrame(20, options, paper, &oracle);
  for (const StereoMatch& m : verified.matches) {
    EXPECT_TRUE(correct(verified.lines[0][m.left].segment, verified.lines[1][m.right].segment));
  }
  // Measured: 13 matches against 9 correct of the plain matcher's.
  EXPECT_GE(static_cast<int>(verified.matches.size()), plain_correct + 3) << plain_correct << " correct without";
  const StereoMatcher::PairCheck none = [](int, int) { return false; };
  EXPECT_TRUE(MatchFrame(20, options, paper, &none).matches.empty());
}

TEST(StereoMatching, AVerifiedPairIsNotAskedTheUnionOverlap) {
  // Paper scene, frame 20, min_union_overlap 0.6: a pair that a verification checks keeps an end
  // hidden in one image (a crossing bar, the image border); only the unverified matches are
  // bound by the union overlap. The verification: the oracle of the test above.
  const RenderedPaper paper(21);
  FrontEndOptions options;
  options.matching.min_union_overlap = 0.6;
  const ProjectedGroundTruth truth[2] = {paper.Projected(20, 0), paper.Projected(20, 1)};
  const MatchedPair plain = MatchFrame(20, options, paper);
  std::vector<int> common;
  const auto correct = [&](const Segment2d& l, const Segment2d& r) {
    return JudgeStereoPair(truth[0], truth[1], l, r, &common) == PairVerdict::kCorrect;
  };
  const StereoMatcher::PairCheck oracle = [&](int l, int r) {
    return correct(plain.lines[0][l].segment, plain.lines[1][r].segment);
  };
  const MatchedPair verified = MatchFrame(20, options, paper, &oracle);
  const StereoGeometry geometry(paper.rig());
  const double sine = std::sin(options.matching.epipolar_angle_deg * M_PI / 180.0);
  const auto below = [&](const MatchedPair& pair) {
    int count = 0;
    for (const StereoMatch& m : pair.matches) {
      count += geometry.BeamOverlap(pair.lines[0][m.left].segment, pair.lines[1][m.right].segment, sine,
                                    options.matching.epipolar_distance_px, StereoGeometry::OverlapOf::kUnion) < 0.6;
    }
    return count;
  };
  EXPECT_EQ(below(plain), 0);
  EXPECT_GT(below(verified), 0) << verified.matches.size() << " verified matches";
  for (const StereoMatch& m : verified.matches) {
    EXPECT_TRUE(correct(verified.lines[0][m.left].segment, verified.lines[1][m.right].segment));
  }
}

TEST(StereoMatching, TemporalCheckSeparatesLookAlikeBarsOfThePaperScene) {
  // The paper scene's bars look alike: the matcher alone pairs edges of different bars (see
  // docs/frontend.md). Moved into the previous pair by the true motion, a correct pair's 3-D
  // line lies on its edges there, a wrong one's does not.
  // The matches of LSD's detections (the default detector when this was measured; the check
  // does not depend on the detector, and EDLines' three frames give one wrong pair fewer than
  // the test needs).
  const RenderedPaper paper(61);
  FrontEndOptions options;
  options.detection.detector = LineDetectorType::kLsd;
  const LineFlowTracker flow(options.tracking);
  SnapWorkspace workspace;
  int correct = 0, correct_seen = 0, wrong = 0, wrong_seen = 0;
  std::vector<int> common;
  for (const int frame : {20, 40, 60}) {
    const MatchedPair pair = MatchFrame(frame, options, paper);
    ImagePyramid previous[2];
    for (int c = 0; c < 2; ++c) flow.BuildPyramid(paper.Image(frame - 1, c), &previous[c]);
    const cv::Mat derivatives[2] = {previous[0][1], previous[1][1]};
    const Rigid3d previous_from_current = paper.Motion(frame, frame - 1);
    const ProjectedGroundTruth truth[2] = {paper.Projected(frame, 0), paper.Projected(frame, 1)};
    for (const StereoMatch& m : pair.matches) {
      const Segment2d& l = pair.lines[0][m.left].segment;
      const Segment2d& r = pair.lines[1][m.right].segment;
      const PairVerdict verdict = JudgeStereoPair(truth[0], truth[1], l, r, &common);
      if (verdict == PairVerdict::kUnjudged) continue;
      const bool seen = SeenInPreviousPair(paper.rig(), previous_from_current, l, r, derivatives, options.tracking, 2.0,
                                           &workspace);
      (verdict == PairVerdict::kCorrect ? correct : wrong) += 1;
      (verdict == PairVerdict::kCorrect ? correct_seen : wrong_seen) += seen;
    }
  }
  ASSERT_GE(correct, 20);
  ASSERT_GE(wrong, 10) << "the test needs wrong matches";
  EXPECT_GE(correct_seen, 0.9 * correct) << correct_seen << " of " << correct;
  // Measured: 42 of 43 correct and 10 of 31 wrong pairs seen (within 2 px).
  EXPECT_LE(wrong_seen, 0.4 * wrong) << wrong_seen << " of " << wrong;
}

TEST(StereoGeometry, BeamOverlapOfRectifiedSegments) {
  StereoRig rig;  // the default rig: rectified, right camera at +x
  const StereoGeometry geometry(rig);
  ASSERT_TRUE(geometry.rectified());
  // A vertical segment rows 100..200 and a right one rows 150..250: overlap 50 of 100.
  EXPECT_NEAR(geometry.BeamOverlap(Segment2d(300, 100, 300, 200), Segment2d(280, 150, 280, 250), 0.1, 1.5), 0.5,
              1e-9);
  EXPECT_EQ(geometry.BeamOverlap(Segment2d(300, 100, 300, 200), Segment2d(280, 210, 280, 250), 0.1, 1.5), 0.0);
  // Horizontal segments: on the same row or not.
  EXPECT_EQ(geometry.BeamOverlap(Segment2d(100, 120, 200, 120), Segment2d(80, 120.5, 180, 120.8), 0.1, 1.5), 1.0);
  EXPECT_EQ(geometry.BeamOverlap(Segment2d(100, 120, 200, 120), Segment2d(80, 124, 180, 124), 0.1, 1.5), 0.0);
  EXPECT_TRUE(geometry.DisparityInRange(Segment2d(300, 100, 300, 200), Segment2d(280, 150, 280, 250), 0, 256));
  EXPECT_FALSE(geometry.DisparityInRange(Segment2d(300, 100, 300, 200), Segment2d(320, 150, 320, 250), 0, 256));
  // Of the union of the rows 100..250, 50 are common.
  EXPECT_NEAR(geometry.BeamOverlap(Segment2d(300, 100, 300, 200), Segment2d(280, 150, 280, 250), 0.1, 1.5,
                                   StereoGeometry::OverlapOf::kUnion),
              1.0 / 3.0, 1e-9);
  // A slanted left line, u = 100 + v / 2, and a vertical right one, u = 100, rows 50..150: the
  // disparity is 50 px at the middle of the common rows, 25 and 75 px at their ends.
  const Segment2d left(100, 0, 200, 200), right(100, 50, 100, 150);
  EXPECT_TRUE(geometry.DisparityInRange(left, right, 20, 80));
  EXPECT_FALSE(geometry.DisparityInRange(left, right, 30, 80));
  EXPECT_FALSE(geometry.DisparityInRange(left, right, 20, 70));
}

TEST(StereoGeometry, BeamOfALineAFewDegreesOffTheEpipolarDirection) {
  // A 3-D line 3.4 deg off the rows, 2-3 m in front of the default rig: it spans 14 rows of
  // each image, which the matcher's test against the epipolar line of the left midpoint (within
  // 1.5 px) refuses; a tracked pair's test accepts the segments of the same line in the two
  // images, which span the same rows.
  using Along = StereoGeometry::AlongEpipolar;
  using Of = StereoGeometry::OverlapOf;
  const StereoRig rig;
  const StereoGeometry geometry(rig);
  const double sine = std::sin(5.0 * M_PI / 180.0);
  const Eigen::Vector3d p(-0.3, 0.2, 2.0), q(0.4, 0.249, 3.0);
  const Eigen::Vector2d pl = rig.left.Project(p), ql = rig.left.Project(q);
  const Eigen::Vector2d pr = rig.right.Project(rig.right_from_left * p), qr = rig.right.Project(rig.right_from_left * q);
  const Segment2d left(pl.x(), pl.y(), ql.x(), ql.y()), right(pr.x(), pr.y(), qr.x(), qr.y());
  ASSERT_LT(geometry.EpipolarSine(left), sine);
  ASSERT_GT(std::abs(ql.y() - pl.y()), 4.0) << "the line must span rows";
  EXPECT_EQ(geometry.BeamOverlap(left, right, sine, 1.5), 0.0);
  EXPECT_EQ(geometry.BeamOverlap(left, right, sine, 1.5, Of::kShorter, Along::kSameExtent), 1.0);
  EXPECT_EQ(geometry.BeamOverlap(left, right, sine, 1.5, Of::kUnion, Along::kSameExtent), 1.0);
  // One end hidden in the left image: the shorter extent still lies within the longer one.
  const Eigen::Vector2d mid = 0.5 * (pl + ql);
  EXPECT_EQ(geometry.BeamOverlap(Segment2d(pl.x(), pl.y(), mid.x(), mid.y()), right, sine, 1.5, Of::kShorter,
                                 Along::kSameExtent),
            1.0);
  // The same right segment 3 rows lower (another line) is outside the beam widened by 1.5 px.
  const Segment2d lower(pr.x(), pr.y() + 3.0, qr.x(), qr.y() + 3.0);
  EXPECT_EQ(geometry.BeamOverlap(left, lower, sine, 1.5, Of::kShorter, Along::kSameExtent), 0.0);
  // A horizontal left segment's row lies within the rows of a vertical right one (such a wrong
  // match appeared on the room's frame 0 when the matcher used this test): a steep right
  // segment is not the image of a line near an epipolar plane.
  EXPECT_EQ(geometry.BeamOverlap(Segment2d(422, 125, 251, 125), Segment2d(225, 126, 225, 250), sine, 1.5,
                                 Of::kShorter, Along::kSameExtent),
            0.0);
}

TEST(StereoGeometry, BeamOfALineNearAnEpipolarPlaneOfARolledRig) {
  // The right camera rolled by 20 deg: the epipolar lines run at -20 deg in the left image and
  // along the rows in the right one, so each image's segment is judged against its own epipole.
  // A 3-D line 0.03 m off the epipolar plane through p (3.4 deg off the left epipolar
  // direction, 3.1 deg off the right one).
  StereoRig rig;
  rig.right_from_left.rotation = Eigen::AngleAxisd(20.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const StereoGeometry geometry(rig);
  ASSERT_FALSE(geometry.rectified());
  const double sine = std::sin(5.0 * M_PI / 180.0);
  const Eigen::Vector3d right_centre = rig.right_from_left.Inverse().translation;
  const Eigen::Vector3d p(-0.3, 0.2, 2.0);
  const Eigen::Vector3d q = 1.5 * p + 5.0 * right_centre + 0.03 * p.cross(right_centre).normalized();
  const Eigen::Vector2d pl = rig.left.Project(p), ql = rig.left.Project(q);
  const Eigen::Vector2d pr = rig.right.Project(rig.right_from_left * p), qr = rig.right.Project(rig.right_from_left * q);
  const Segment2d left(pl.x(), pl.y(), ql.x(), ql.y()), right(pr.x(), pr.y(), qr.x(), qr.y());
  ASSERT_LT(geometry.EpipolarSine(left), sine);
  ASSERT_GT(std::abs(ql.y() - pl.y()), 20.0) << "the left segment must not lie along the rows";
  using Along = StereoGeometry::AlongEpipolar;
  using Of = StereoGeometry::OverlapOf;
  EXPECT_EQ(geometry.BeamOverlap(left, right, sine, 1.5), 0.0);
  EXPECT_EQ(geometry.BeamOverlap(left, right, sine, 1.5, Of::kShorter, Along::kSameExtent), 1.0);
  // The other orientation of the same segments, and the right one 3 px across its epipolar lines.
  EXPECT_EQ(geometry.BeamOverlap(Segment2d(ql.x(), ql.y(), pl.x(), pl.y()), Segment2d(qr.x(), qr.y(), pr.x(), pr.y()),
                                 sine, 1.5, Of::kShorter, Along::kSameExtent),
            1.0);
  EXPECT_EQ(geometry.BeamOverlap(left, Segment2d(pr.x(), pr.y() + 3.0, qr.x(), qr.y() + 3.0), sine, 1.5, Of::kShorter,
                                 Along::kSameExtent),
            0.0);
}

}  // namespace
}  // namespace slt
