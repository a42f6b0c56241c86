#include "frontend/parallel_edges.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace slt {
namespace {

// A bright horizontal bar, rows 58-60 (edges at v = 57.5 and 60.5), blurred as the renderer's
// defocus; `bar` false: a single step at v = 57.5 (brighter below).
cv::Mat Image(bool bar) {
  cv::Mat image(120, 240, CV_8UC1, cv::Scalar(80));
  image(cv::Rect(0, 58, 240, bar ? 3 : 62)).setTo(150);
  cv::GaussianBlur(image, image, cv::Size(0, 0), 0.5);
  return image;
}

std::vector<ImageLine> AfterSearch(const cv::Mat& image, const DetectionOptions& options) {
  const TrackingOptions tracking;
  ImagePyramid pyramid;
  LineFlowTracker(tracking).BuildPyramid(image, &pyramid);
  ImageLine top;  // the bar's upper edge, as a snapped detection
  top.segment = Segment2d(20, 57.5, 220, 57.5);
  top.contrast = OrientByGradient(image, &top.segment);
  std::vector<ImageLine> lines = {top};
  SnapWorkspace workspace;
  AddParallelEdges(options, tracking, image, pyramid[1], &lines, &workspace);
  return lines;
}

TEST(AddParallelEdges, FindsTheSecondEdgeOfAThinBar) {
  DetectionOptions options;
  options.parallel_edge_px = 3.0;
  const std::vector<ImageLine> lines = AfterSearch(Image(true), options);
  ASSERT_EQ(lines.size(), 2u);
  const Segment2d& added = lines[1].segment;
  EXPECT_NEAR(added[1], 60.5, 0.15);
  EXPECT_NEAR(added[3], 60.5, 0.15);
  EXPECT_GT((added.tail<2>() - added.head<2>()).norm(), 180.0);
  // Opposite polarity: brighter above it, so it points the other way from the upper edge.
  EXPECT_LT((added[2] - added[0]) * (lines[0].segment[2] - lines[0].segment[0]), 0.0);
  EXPECT_GT(lines[1].contrast, 30.0f);
}

TEST(AddParallelEdges, AddsNothingBesideASingleEdgeOrWhenOff) {
  DetectionOptions on;
  on.parallel_edge_px = 3.0;
  EXPECT_EQ(AfterSearch(Image(false), on).size(), 1u);
  EXPECT_EQ(AfterSearch(Image(true), DetectionOptions()).size(), 1u);  // off by default
}

}  // namespace
}  // namespace slt
