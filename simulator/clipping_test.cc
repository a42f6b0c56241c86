#include "simulator/clipping.h"

#include <gtest/gtest.h>

namespace slt {
namespace {

// Distance of x from the infinite line through a and b.
double DistanceToLine(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& x) {
  const Eigen::Vector2d d = (b - a).normalized();
  const Eigen::Vector2d r = x - a;
  return std::abs(d.x() * r.y() - d.y() * r.x());
}

TEST(ClipSegmentToImage, KeepsInsideSegmentsAndCutsCrossingOnes) {
  Eigen::Vector2d a(10.0, 20.0), b(600.0, 400.0);
  ASSERT_TRUE(ClipSegmentToImage(640, 480, &a, &b));
  EXPECT_EQ(a, Eigen::Vector2d(10.0, 20.0));
  EXPECT_EQ(b, Eigen::Vector2d(600.0, 400.0));

  const Eigen::Vector2d from(-100.0, 100.0), to(800.0, 300.0);
  a = from;
  b = to;
  ASSERT_TRUE(ClipSegmentToImage(640, 480, &a, &b));
  EXPECT_DOUBLE_EQ(a.x(), 0.0);
  EXPECT_DOUBLE_EQ(b.x(), 639.0);
  EXPECT_LT(DistanceToLine(from, to, a), 1e-9);
  EXPECT_LT(DistanceToLine(from, to, b), 1e-9);

  a = {-50.0, 500.0};  // crosses the bottom-left corner region only
  b = {50.0, 470.0};
  ASSERT_TRUE(ClipSegmentToImage(640, 480, &a, &b));
  EXPECT_DOUBLE_EQ(a.y(), 479.0);
  EXPECT_EQ(b, Eigen::Vector2d(50.0, 470.0));
}

TEST(ClipSegmentToImage, RejectsSegmentsOutside) {
  Eigen::Vector2d a(-10.0, -5.0), b(-1.0, 400.0);  // left of the image
  EXPECT_FALSE(ClipSegmentToImage(640, 480, &a, &b));
  a = {-100.0, 50.0};  // its line crosses the image, the segment does not reach it
  b = {-10.0, 60.0};
  EXPECT_FALSE(ClipSegmentToImage(640, 480, &a, &b));
  a = {700.0, -50.0};  // diagonal past the top-right corner
  b = {600.0, -10.0};
  EXPECT_FALSE(ClipSegmentToImage(640, 480, &a, &b));
  a = {100.0, 480.5};  // horizontal just below the last row
  b = {300.0, 480.5};
  EXPECT_FALSE(ClipSegmentToImage(640, 480, &a, &b));
}

TEST(ClipSegmentToDepth, KeepsThePartInFront) {
  Eigen::Vector3d p(0.0, 0.0, 1.0), q(1.0, 2.0, 3.0);
  ASSERT_TRUE(ClipSegmentToDepth(0.05, &p, &q));
  EXPECT_EQ(p, Eigen::Vector3d(0.0, 0.0, 1.0));

  p = {0.0, 0.0, -1.0};
  q = {2.0, 4.0, 1.0};
  ASSERT_TRUE(ClipSegmentToDepth(0.5, &p, &q));
  EXPECT_EQ(p.z(), 0.5);
  EXPECT_TRUE(p.isApprox(Eigen::Vector3d(1.5, 3.0, 0.5), 1e-12));
  EXPECT_EQ(q, Eigen::Vector3d(2.0, 4.0, 1.0));

  p = {0.0, 0.0, 0.01};
  q = {1.0, 0.0, -2.0};
  EXPECT_FALSE(ClipSegmentToDepth(0.05, &p, &q));
}

}  // namespace
}  // namespace slt
