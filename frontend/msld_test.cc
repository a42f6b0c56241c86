#include "frontend/msld.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

#include "frontend/image_sampling.h"

namespace slt {
namespace {

// The definition of msld.h evaluated point by point (bilinear samples of the smoothed image at
// every q(i, s, c) +- d, n): the slow reference the vectorised extractor must reproduce.
MsldDescriptor ReferenceMsld(const cv::Mat& smoothed, const Segment2d& segment) {
  const Eigen::Vector2d a = segment.head<2>(), b = segment.tail<2>();
  const double length = (b - a).norm();
  const Eigen::Vector2d d = (b - a) / length, n(-d.y(), d.x());
  const int pixels = static_cast<int>(std::floor(length)) + 1;
  constexpr int kFeatures = 36;
  const auto sample = [&](const Eigen::Vector2d& p) {
    return static_cast<double>(SampleBilinear<float>(smoothed, static_cast<float>(p.x()), static_cast<float>(p.y())));
  };
  Eigen::Matrix<double, kFeatures, Eigen::Dynamic> v(kFeatures, pixels);
  v.setZero();
  for (int i = 0; i < pixels; ++i) {
    const Eigen::Vector2d p = a + i * d;
    for (int s = -2; s <= 2; ++s) {
      for (int c = -22; c <= 22; ++c) {
        const Eigen::Vector2d q = p + s * d + c * n;
        const double w = std::exp(-c * c / (2.0 * 22.5 * 22.5));
        const double gd = 0.5 * (sample(q + d) - sample(q - d)) * w;
        const double gn = 0.5 * (sample(q + n) - sample(q - n)) * w;
        const int j = (c + 22) / 5;
        v(4 * j + 0, i) += std::max(gn, 0.0);
        v(4 * j + 1, i) += std::max(-gn, 0.0);
        v(4 * j + 2, i) += std::max(gd, 0.0);
        v(4 * j + 3, i) += std::max(-gd, 0.0);
      }
    }
  }
  const Eigen::Matrix<double, kFeatures, 1> mean = v.rowwise().mean();
  Eigen::Matrix<double, kFeatures, 1> std_dev =
      ((v.colwise() - mean).array().square().rowwise().sum() / pixels).sqrt().matrix();
  Eigen::Matrix<double, 72, 1> out;
  out << mean.normalized(), std_dev.normalized();
  out = out.cwiseMin(0.4);
  return out.normalized().cast<float>();
}

// A textured image with a bright quadrilateral: straight edges with texture around them.
cv::Mat TestImage(int width, int height, std::uint32_t seed) {
  cv::Mat noise(height / 8 + 1, width / 8 + 1, CV_8UC1);
  std::mt19937 rng(seed);
  for (int v = 0; v < noise.rows; ++v) {
    for (int u = 0; u < noise.cols; ++u) noise.at<uchar>(v, u) = static_cast<uchar>(60 + rng() % 60);
  }
  cv::Mat image;
  cv::resize(noise, image, cv::Size(width, height), 0, 0, cv::INTER_CUBIC);
  const std::vector<cv::Point> quad = {{60, 50}, {200, 70}, {190, 180}, {70, 160}};
  cv::fillConvexPoly(image, quad, cv::Scalar(200), cv::LINE_AA);
  return image;
}

TEST(Msld, FastExtractorMatchesThePointByPointDefinition) {
  const cv::Mat image = TestImage(256, 224, 3);
  MsldExtractor extractor;
  extractor.SetImage(image);
  // Edges of the quadrilateral both ways round, a line through texture only, a line crossing
  // the border (clamped samples) and sub-pixel endpoints.
  const std::vector<Segment2d> segments = {
      Segment2d(60, 50, 200, 70),       Segment2d(190, 180, 70, 160),   Segment2d(200.3, 70.6, 190.2, 179.9),
      Segment2d(20.5, 200.2, 110.7, 205.1), Segment2d(2.0, 10.0, 2.0, 120.0), Segment2d(100, 100, 103.5, 101)};
  for (const Segment2d& s : segments) {
    MsldDescriptor fast;
    ASSERT_TRUE(extractor.Compute(s, &fast));
    const MsldDescriptor slow = ReferenceMsld(extractor.smoothed(), s);
    EXPECT_NEAR(fast.norm(), 1.0f, 1e-5f);
    EXPECT_LT((fast - slow).cwiseAbs().maxCoeff(), 2e-4f) << "segment " << s.transpose();
  }
}

TEST(Msld, StepEdgeHasOnlyPositiveNormalGradient) {
  // Vertical step, brighter on the +n side of the segment (the front end's orientation): for a
  // segment going down (+v), d = (0, 1) and n = (-1, 0), so brighter to the left.
  cv::Mat image(120, 120, CV_8UC1, cv::Scalar(50));
  image(cv::Rect(0, 0, 60, 120)).setTo(200);
  MsldExtractor extractor;
  extractor.SetImage(image);
  MsldDescriptor descriptor;
  ASSERT_TRUE(extractor.Compute(Segment2d(59.5, 20, 59.5, 100), &descriptor));
  for (int j = 0; j < MsldLayout::kSubRegions; ++j) {
    EXPECT_NEAR(descriptor[4 * j + 1], 0.0f, 1e-4f) << "negative normal gradient in sub-region " << j;
    EXPECT_NEAR(descriptor[4 * j + 2], 0.0f, 1e-4f) << "gradient along the line in sub-region " << j;
    EXPECT_NEAR(descriptor[4 * j + 3], 0.0f, 1e-4f);
  }
  // The central sub-region carries the step; clipped at 0.4 before renormalisation.
  EXPECT_GT(descriptor[4 * 4 + 0], 0.3f);
  // The same edge described the other way round sees a negative normal gradient instead.
  MsldDescriptor reversed;
  ASSERT_TRUE(extractor.Compute(Segment2d(59.5, 100, 59.5, 20), &reversed));
  EXPECT_GT(reversed[4 * 4 + 1], 0.3f);
  EXPECT_NEAR(reversed[4 * 4 + 0], 0.0f, 1e-4f);
}

TEST(Msld, InvariantToAffineIntensityChangeAndDistinctive) {
  const cv::Mat image = TestImage(256, 224, 5);
  cv::Mat brighter;
  image.convertTo(brighter, CV_8U, 0.8, 30.0);
  MsldExtractor a, b;
  a.SetImage(image);
  b.SetImage(brighter);
  const Segment2d edge(60, 50, 200, 70), other(70, 160, 60, 50);
  MsldDescriptor da, db, dother;
  ASSERT_TRUE(a.Compute(edge, &da));
  ASSERT_TRUE(b.Compute(edge, &db));
  ASSERT_TRUE(a.Compute(other, &dother));
  EXPECT_LT((da - db).norm(), 0.02f);  // only 8-bit rounding differs
  EXPECT_GT((da - dother).norm(), 0.3f);
}

TEST(Msld, RejectsTooShortSegments) {
  MsldExtractor extractor;
  extractor.SetImage(cv::Mat(50, 50, CV_8UC1, cv::Scalar(0)));
  MsldDescriptor descriptor;
  EXPECT_FALSE(extractor.Compute(Segment2d(10, 10, 11, 10.5), &descriptor));
  EXPECT_TRUE(extractor.Compute(Segment2d(10, 10, 13, 10), &descriptor));
}

}  // namespace
}  // namespace slt
