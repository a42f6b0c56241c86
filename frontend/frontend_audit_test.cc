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

}  // namespace
}  // namespace slt
