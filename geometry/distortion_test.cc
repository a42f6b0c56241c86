#include "geometry/distortion.h"

#include <gtest/gtest.h>

namespace slt {
namespace {

// EuRoC V1_01's cam0 (sensor.yaml).
const RadialTangential kEuroc = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};

TEST(Distortion, KnownValue) {
  // x = 0.5, y = -0.2: r2 = 0.29, radial = 1 + 0.1 * 0.29 + 0.01 * 0.0841 = 1.029841.
  const RadialTangential d = {0.1, 0.01, 0.002, -0.003};
  const Eigen::Vector2d out = DistortNormalized({0.5, -0.2}, d);
  EXPECT_NEAR(out.x(), 0.5 * 1.029841 + 2 * 0.002 * 0.5 * -0.2 + -0.003 * (0.29 + 2 * 0.25), 1e-15);
  EXPECT_NEAR(out.y(), -0.2 * 1.029841 + 0.002 * (0.29 + 2 * 0.04) + 2 * -0.003 * 0.5 * -0.2, 1e-15);
  EXPECT_EQ(DistortNormalized({0.5, -0.2}, RadialTangential{}), Eigen::Vector2d(0.5, -0.2));
}

TEST(Distortion, UndistortInvertsDistortOverAWideField) {
  // The corners of EuRoC's 752 x 480 image are at |x| <= 0.8, |y| <= 0.55 in normalised
  // coordinates; strong barrel distortion there.
  for (double x = -0.9; x <= 0.9; x += 0.05) {
    for (double y = -0.6; y <= 0.6; y += 0.05) {
      const Eigen::Vector2d distorted = DistortNormalized({x, y}, kEuroc);
      const Eigen::Vector2d back = UndistortNormalized(distorted, kEuroc);
      EXPECT_NEAR(back.x(), x, 1e-10);
      EXPECT_NEAR(back.y(), y, 1e-10);
    }
  }
  EXPECT_GT((DistortNormalized({0.8, 0.5}, kEuroc) - Eigen::Vector2d(0.8, 0.5)).norm(), 0.1);
}

}  // namespace
}  // namespace slt
