#include "geometry/stereo_point.h"

#include <gtest/gtest.h>

#include "geometry/numeric_jacobian.h"
#include "geometry/se3.h"

namespace slt {
namespace {

// A rig that is not rectified: the right camera turned and raised, other intrinsics.
StereoRig TurnedRig() {
  StereoRig rig;
  rig.right.fx = 820.0;
  rig.right.fy = 815.0;
  rig.right.cx = 330.0;
  rig.right.cy = 236.0;
  Vector6d xi;
  xi << -0.1, 0.004, 0.01, 0.01, -0.03, 0.02;
  rig.right_from_left = ExpSE3(xi);
  return rig;
}

// On the point's own projections, Point returns the point; its Jacobian is the central
// differences'; in a rectified rig its depth is f b / disparity.
TEST(StereoPointGeometry, PlacesThePointOfTwoProjections) {
  const Eigen::Vector3d x(0.12, -0.07, 0.8);
  for (const StereoRig& rig : {StereoRig(), TurnedRig()}) {
    const StereoPointGeometry geometry(rig);
    const Eigen::Vector2d left = rig.left.Project(x), right = rig.right.Project(rig.right_from_left * x);
    EXPECT_LT(geometry.EpipolarDistance(left, right), 1e-9);
    ReferencePoint p;
    geometry.Point(left, right, true, &p);
    EXPECT_LT((p.point - x).norm(), 1e-9);
    EXPECT_NEAR(p.depth, x.z(), 1e-9);
    const auto point_of = [&](const Eigen::Vector4d& pixels) -> Eigen::Vector3d {
      ReferencePoint q;
      geometry.Point(pixels.head<2>(), pixels.tail<2>(), false, &q);
      return q.point;
    };
    Eigen::Vector4d pixels;
    pixels << left, right;
    const Eigen::Matrix<double, 3, 4> numeric = CentralDifferenceJacobian<3, 4>(point_of, pixels, 1e-4);
    EXPECT_LT((p.point_d_pixels - numeric).norm(), 1e-6 * numeric.norm());
  }
  const StereoRig rig;
  const StereoPointGeometry geometry(rig);
  ReferencePoint p;
  geometry.Point({300.0, 200.0}, {258.0, 201.0}, false, &p);  // 42 px of disparity, a row off
  EXPECT_NEAR(p.depth, rig.left.fx * rig.Baseline() / 42.0, 1e-9);
}

// Across the epipolar lines the distances pair the endpoints; along them (a horizontal line of
// a horizontal rig) the segments' directions do.
TEST(StereoPointGeometry, PairsEndpoints) {
  const StereoPointGeometry geometry{StereoRig()};
  const Segment2d left(100.0, 50.0, 110.0, 150.0), right(80.0, 50.0, 90.0, 150.0);
  const Segment2d reversed(90.0, 150.0, 80.0, 50.0);
  EXPECT_FALSE(StereoEndpointsSwapped(geometry, left, right, 1.0));
  EXPECT_TRUE(StereoEndpointsSwapped(geometry, left, reversed, 1.0));
  const Segment2d horizontal(100.0, 80.0, 200.0, 80.0), horizontal_right(70.0, 80.0, 170.0, 80.0);
  EXPECT_FALSE(StereoEndpointsSwapped(geometry, horizontal, horizontal_right, 1.0));
  EXPECT_TRUE(StereoEndpointsSwapped(geometry, horizontal, Segment2d(170.0, 80.0, 70.0, 80.0), 1.0));
}

}  // namespace
}  // namespace slt
