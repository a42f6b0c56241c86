#include "frontend/parallel_edges.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "common/random.h"

namespace slt {
namespace {

// 240 x 120 images of horizontal bands (rows first_row .. last_row of a grey level), blurred
// as the renderer's defocus, with the renderer's noise level (sigma ~2.2 grey levels).
struct Band {
  int first_row, last_row;
  double level;
};
cv::Mat Image(double background, const std::vector<Band>& bands, std::uint64_t seed = 3) {
  cv::Mat image(120, 240, CV_32FC1, cv::Scalar(background));
  for (const Band& band : bands) image.rowRange(band.first_row, band.last_row + 1).setTo(band.level);
  cv::GaussianBlur(image, image, cv::Size(0, 0), 0.7);
  RandomStream random = MakeStream(seed, "parallel_edges_test");
  std::normal_distribution<float> noise(0.0f, 2.2f);
  for (int v = 0; v < image.rows; ++v) {
    for (int u = 0; u < image.cols; ++u) image.at<float>(v, u) += noise(random);
  }
  cv::Mat grey;
  image.convertTo(grey, CV_8UC1);
  return grey;
}

// The detection on the edge at row boundary v (between rows v - 0.5 and v + 0.5), oriented.
ImageLine Detection(const cv::Mat& image, double v, double u0 = 20.0, double u1 = 220.0) {
  ImageLine line;
  line.segment = Segment2d(u0, v, u1, v);
  line.contrast = OrientByGradient(image, &line.segment);
  return line;
}

DetectionOptions On(double parallel_edge_px) {
  DetectionOptions options;
  options.parallel_edge_px = parallel_edge_px;
  return options;
}

constexpr double kMinGradient = 1.0;  // TrackingOptions::snap_min_gradient's default

// The lines after the search beside `detection` (4 px); the one added must be horizontal at
// row boundary v (within tolerance) and point the same way as the detection or not.
std::vector<ImageLine> ExpectOneAdded(const cv::Mat& image, const ImageLine& detection, double v, double tolerance,
                                      bool same_direction) {
  std::vector<ImageLine> lines = {detection};
  AddParallelEdges(On(4.0), kMinGradient, image, &lines);
  EXPECT_EQ(lines.size(), 2u);
  if (lines.size() != 2u) return lines;
  const Segment2d& added = lines[1].segment;
  EXPECT_NEAR(added[1], v, tolerance);
  EXPECT_NEAR(added[3], v, tolerance);
  EXPECT_EQ((added[2] - added[0]) * (detection.segment[2] - detection.segment[0]) > 0.0, same_direction);
  return lines;
}

TEST(AddParallelEdges, FindsTheSecondEdgeOfAThinBar) {
  // A bright bar, rows 58-60: edges at v = 57.5 and 60.5; the detection on the upper one.
  const cv::Mat image = Image(80, {{58, 60, 150}});
  // Opposite polarity: brighter above it, so it points the other way from the upper edge.
  const std::vector<ImageLine> lines = ExpectOneAdded(image, Detection(image, 57.5), 60.5, 0.15, false);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_GT((lines[1].segment.tail<2>() - lines[1].segment.head<2>()).norm(), 180.0);
  EXPECT_GT(lines[1].contrast, 30.0f);
}

TEST(AddParallelEdges, FindsAWeakEdgeThreePixelsFromAStrongOneOfTheSamePolarity) {
  // A shelf's front face seen from above: background 80, a face of 92 three rows high (weak
  // step at v = 57.5), then 150 (strong step at v = 60.5). The Scharr derivative the snap uses
  // merges the two into one peak; the profile does not.
  const cv::Mat image = Image(80, {{58, 60, 92}, {61, 119, 150}});
  // The same polarity: it points the same way as the strong edge.
  const std::vector<ImageLine> lines = ExpectOneAdded(image, Detection(image, 60.5), 57.5, 0.3, true);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NEAR(lines[1].contrast, 12.0f, 3.0f);
  // Below the contrast bound it is not an edge.
  DetectionOptions strict = On(4.0);
  strict.min_contrast = 20.0;
  std::vector<ImageLine> strict_lines = {Detection(image, 60.5)};
  AddParallelEdges(strict, kMinGradient, image, &strict_lines);
  EXPECT_EQ(strict_lines.size(), 1u);
}

TEST(AddParallelEdges, TheDefaultsKeepASixLevelStepThatTheFormerContrastBoundDropped) {
  // Weak step 80 -> 86 at v = 57.5, strong 86 -> 150 at v = 60.5. Its own step (measured ~7
  // with this noise; at 6 levels the search finds it under about half of the noise draws) is
  // above the default min_contrast 5 and the noise of a two-pixel difference (3.1), below the
  // 8 of before the second edges.
  const cv::Mat image = Image(80, {{58, 60, 86}, {61, 119, 150}});
  std::vector<ImageLine> lines = {Detection(image, 60.5)};
  AddParallelEdges(DetectionOptions(), kMinGradient, image, &lines);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NEAR(lines[1].segment[1], 57.5, 0.4);
  EXPECT_NEAR(lines[1].segment[3], 57.5, 0.4);
  EXPECT_GT(lines[1].contrast, 5.0f);
  EXPECT_LT(lines[1].contrast, 8.0f);
  DetectionOptions former;
  former.min_contrast = 8.0;
  std::vector<ImageLine> former_lines = {Detection(image, 60.5)};
  AddParallelEdges(former, kMinGradient, image, &former_lines);
  EXPECT_EQ(former_lines.size(), 1u);
}

TEST(AddParallelEdges, ReplacesAShorterPieceOfTheSecondEdge) {
  const cv::Mat image = Image(80, {{58, 60, 150}});
  // The lower edge detected only on its first 50 px (and pointing as the gradient says).
  std::vector<ImageLine> lines = {Detection(image, 57.5), Detection(image, 60.5, 20.0, 70.0)};
  AddParallelEdges(On(4.0), kMinGradient, image, &lines);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NEAR(lines[0].segment[1], 57.5, 1e-9);  // the upper edge, unchanged
  EXPECT_NEAR(lines[1].segment[1], 60.5, 0.15);
  EXPECT_GT((lines[1].segment.tail<2>() - lines[1].segment.head<2>()).norm(), 180.0);
  // Found whole: nothing added.
  std::vector<ImageLine> both = {Detection(image, 57.5), Detection(image, 60.5)};
  AddParallelEdges(On(4.0), kMinGradient, image, &both);
  EXPECT_EQ(both.size(), 2u);
}

TEST(AddParallelEdges, AddsNothingBesideASingleEdgeOrWhenOff) {
  const cv::Mat step = Image(80, {{58, 119, 150}});
  std::vector<ImageLine> lines = {Detection(step, 57.5)};
  AddParallelEdges(On(4.0), kMinGradient, step, &lines);
  EXPECT_EQ(lines.size(), 1u);
  const cv::Mat bar = Image(80, {{58, 60, 150}});
  std::vector<ImageLine> off = {Detection(bar, 57.5)};
  AddParallelEdges(On(0.0), kMinGradient, bar, &off);
  EXPECT_EQ(off.size(), 1u);
}

}  // namespace
}  // namespace slt
