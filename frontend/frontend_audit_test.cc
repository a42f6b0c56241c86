#include "frontend/frontend_audit.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace slt {
namespace {

// A vertical edge at u = 99.5 between grey levels `left` and `right`, blurred as the renderer's
// defocus (0.5 px), and a horizontal one at v = 59.5 with no step at all.
cv::Mat TwoEdges(int left, int right) {
  cv::Mat image(120, 200, CV_8UC1, cv::Scalar(left));
  image.colRange(100, 200).setTo(right);
  cv::GaussianBlur(image, image, cv::Size(0, 0), 0.5);
  return image;
}

TEST(MeasureEdgeStep, IsTheGreyLevelStepAcrossTheSegmentAndItsMeanLevel) {
  const cv::Mat image = TwoEdges(100, 120);
  const EdgeStep vertical = MeasureEdgeStep(image, Segment2d(99.5, 10, 99.5, 110));
  EXPECT_NEAR(vertical.step, 20.0, 0.5);
  EXPECT_NEAR(vertical.level, 110.0, 0.5);
  // Reversing the segment does not change it; a segment on a flat area has no step.
  EXPECT_NEAR(MeasureEdgeStep(image, Segment2d(99.5, 110, 99.5, 10)).step, vertical.step, 1e-9);
  EXPECT_NEAR(MeasureEdgeStep(image, Segment2d(10, 59.5, 90, 59.5)).step, 0.0, 1e-9);
  // The median: an edge with a step along only a third of its length has none.
  cv::Mat partial(120, 200, CV_8UC1, cv::Scalar(100));
  partial(cv::Rect(100, 10, 100, 33)).setTo(160);
  EXPECT_LT(MeasureEdgeStep(partial, Segment2d(99.5, 10, 99.5, 110)).step, 1.0);
}

TEST(PhotometricallyVisible, KeepsTheEdgesWhoseStepIsAboveTheNoiseOfATwoPixelDifference) {
  ImageConfig images;  // read noise 1.5, shot noise 0.03: sigma 2.3 at level 100, sqrt(2) sigma 3.3
  const std::vector<LineObservation> edge = {{7, Segment2d(99.5, 10, 99.5, 110)}};
  EXPECT_EQ(PhotometricallyVisible(edge, TwoEdges(99, 101), images).size(), 0u);    // 2 levels: 0.6x
  ASSERT_EQ(PhotometricallyVisible(edge, TwoEdges(97, 103), images).size(), 1u);    // 6 levels: 1.8x
  EXPECT_EQ(PhotometricallyVisible(edge, TwoEdges(97, 103), images)[0].id, 7);
  EXPECT_EQ(PhotometricallyVisible(edge, TwoEdges(97, 103), images, 2.0).size(), 0u);  // under 2x
  images.read_noise = 0.5;
  images.shot_noise = 0.0;  // sqrt(2) sigma 0.7: 2 levels are well above
  EXPECT_EQ(PhotometricallyVisible(edge, TwoEdges(99, 101), images).size(), 1u);
  // Without image noise (sigma 0) an edge with a step is visible, one without a step is not.
  images.read_noise = 0.0;
  EXPECT_EQ(PhotometricallyVisible(edge, TwoEdges(99, 101), images).size(), 1u);
  EXPECT_EQ(PhotometricallyVisible(edge, TwoEdges(100, 100), images).size(), 0u);
}

TEST(WithBarSecondEdges, AppendsTheOtherLongEdgeOfEachPaperSceneBar) {
  const SimulatedSequence paper = Simulate(SimulationConfigFromJson(RenderedPaperConfig(2), "test"));
  const std::vector<Line3d> lines = WithBarSecondEdges(paper);
  const size_t n = paper.lines.size();
  ASSERT_EQ(lines.size(), 2 * n);
  for (size_t i = 0; i < n; ++i) {
    const Line3d &line = lines[i], &second = lines[n + i];
    // Parallel, as long, in the same order, 4 mm beside it (the bar's width).
    EXPECT_LT(((line.q - line.p) - (second.q - second.p)).norm(), 1e-9);
    EXPECT_NEAR((second.p - line.p).norm(), 0.004, 1e-9);
    EXPECT_NEAR((second.p - line.p).dot(line.q - line.p), 0.0, 1e-9);
  }
  // The room's lines are the edges of its surfaces already: nothing is added.
  const SimulatedSequence room = Simulate(SimulationConfigFromJson(RenderedRoomConfig(2, false), "test"));
  EXPECT_EQ(WithBarSecondEdges(room).size(), room.lines.size());
}

TEST(WithErrorReplaced, PutsTheLinesOnTheTruthWithTheChosenNoiseAndKeepsTheRest) {
  const SimulatedSequence paper = Simulate(SimulationConfigFromJson(RenderedPaperConfig(3), "test"));
  // The simulator's observations (ids = ground-truth lines) as a front end's output with a
  // systematic error: every endpoint 0.7 px across its line and 3 px along it; the pair of id
  // 0 made wrong (its right segment another line's).
  // A front end's frames hold the same ids in the same order in both images.
  StereoSequence observed = paper.sequence;
  for (StereoFrame& frame : observed.frames) {
    std::vector<LineObservation> left, right;
    for (const LineObservation& l : frame.left) {
      for (const LineObservation& r : frame.right) {
        if (r.id != l.id) continue;
        left.push_back(l);
        right.push_back(r);
      }
    }
    frame.left = left;
    frame.right = right;
    for (auto* image : {&frame.left, &frame.right}) {
      for (LineObservation& o : *image) {
        const Eigen::Vector2d d = (o.segment.tail<2>() - o.segment.head<2>()).normalized(), n(-d.y(), d.x());
        o.segment.head<2>() += 0.7 * n + 3.0 * d;
        o.segment.tail<2>() += 0.7 * n + 3.0 * d;
      }
    }
    ASSERT_GE(frame.right.size(), 2u);
    ASSERT_EQ(frame.right[0].id, 0);
    frame.right[0].segment = frame.right[1].segment;
  }
  const std::vector<Line3d> lines = WithBarSecondEdges(paper);
  const auto across = [&](const StereoSequence& sequence, double* rms, int* wrong_kept, double* along_moved) {
    double sq = 0.0, along = 0.0;
    int count = 0;
    *wrong_kept = 0;
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 2; ++c) {
        const ProjectedGroundTruth truth = ProjectedGroundTruthAt(paper, k, c);
        const auto& in = c == 0 ? observed.frames[k].left : observed.frames[k].right;
        const auto& out = c == 0 ? sequence.frames[k].left : sequence.frames[k].right;
        ASSERT_EQ(in.size(), out.size());
        for (size_t i = 0; i < out.size(); ++i) {
          if (out[i].id == 0) {
            *wrong_kept += out[i].segment == in[i].segment;
            continue;
          }
          sq += truth.EndpointDistances(out[i].segment, static_cast<int>(out[i].id)).squaredNorm();
          count += 2;
          const Eigen::Vector2d d = (in[i].segment.tail<2>() - in[i].segment.head<2>()).normalized();
          along = std::max(along, std::abs(d.dot(out[i].segment.head<2>() - in[i].segment.head<2>())));
        }
      }
    }
    ASSERT_GT(count, 300);
    *rms = std::sqrt(sq / count);
    *along_moved = along;
  };
  double rms = 0.0, along = 0.0;
  int wrong_kept = 0;
  across(WithErrorReplaced(paper, lines, observed, 0.0, 5), &rms, &wrong_kept, &along);
  EXPECT_LT(rms, 1e-6);      // on the truth: the 0.7 px are gone
  EXPECT_LT(along, 0.05);    // moved across only (the line's direction differs by < 1 deg)
  EXPECT_EQ(wrong_kept, 6);  // the wrong pair as measured, 3 frames x 2 images
  across(WithErrorReplaced(paper, lines, observed, 0.5, 5), &rms, &wrong_kept, &along);
  EXPECT_NEAR(rms, 0.5, 0.05);
  EXPECT_EQ(wrong_kept, 6);
}

}  // namespace
}  // namespace slt
