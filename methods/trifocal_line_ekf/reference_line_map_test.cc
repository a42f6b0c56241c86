#include "methods/trifocal_line_ekf/reference_line_map.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "geometry/se3.h"
#include "optim/line_sfm_manifolds.h"

namespace slt {
namespace {

// The 3-D line through p and q (moment p x d, unit d) with a tangent covariance.
ReferenceLineMap::Line MapLine(const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  ReferenceLineMap::Line line;
  line.line.direction = (q - p).normalized();
  line.line.moment = p.cross(line.line.direction);
  double parameters[kLineAmbientSize];
  EXPECT_TRUE(LineToParameters(line.line, parameters));
  line.line_d_tangent = LineTangentBasis(parameters);
  Eigen::Matrix4d a;
  a << 2, 0.3, 0, 0.1, 0.3, 1, 0.2, 0, 0, 0.2, 3, 0.4, 0.1, 0, 0.4, 1.5;
  line.tangent_covariance = 1e-6 * a;
  return line;
}

// The segment from p to q (left-camera frame) in the left (c = 0) or right image.
Segment2d Projected(const StereoRig& rig, int c, const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  const PinholeCamera& camera = c == 0 ? rig.left : rig.right;
  const Rigid3d cam_from_left = c == 0 ? Rigid3d() : rig.right_from_left;
  Segment2d s;
  s << camera.Project(cam_from_left * p), camera.Project(cam_from_left * q);
  return s;
}

const Eigen::Vector3d kP(-0.4, -0.3, 2.5), kQ(0.3, 0.4, 2.9);

TEST(ReferenceLineMap, MovesALineAndItsCovarianceIntoTheNewFrameAndBack) {
  ReferenceLineMap map(5);
  const ReferenceLineMap::Line line = MapLine(kP, kQ);
  map.Keep(7, line);
  const Rigid3d new_from_old{ExpSO3(Eigen::Vector3d(0.02, -0.05, 0.01)), Eigen::Vector3d(0.1, -0.02, 0.05)};
  map.Move(new_from_old);
  ASSERT_NE(map.Find(7), nullptr);
  const ReferenceLineMap::Line moved = *map.Find(7);
  const PlueckerLine expected = TransformPluecker(new_from_old, line.line);
  EXPECT_LT((moved.line.direction - expected.direction).norm(), 1e-12);
  EXPECT_LT((moved.line.moment - expected.moment).norm(), 1e-12);
  // The covariance of the tangent changes with the basis at the moved line, not the spread of
  // [n; d] it describes: B C B^T moves as A B C B^T A^T.
  Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Zero();
  a.topLeftCorner<3, 3>() = new_from_old.rotation;
  a.topRightCorner<3, 3>() = Skew(new_from_old.translation) * new_from_old.rotation;
  a.bottomRightCorner<3, 3>() = new_from_old.rotation;
  const Eigen::Matrix<double, 6, 6> ambient = a * line.line_d_tangent * line.tangent_covariance *
                                              line.line_d_tangent.transpose() * a.transpose();
  const Eigen::Matrix<double, 6, 6> moved_ambient =
      moved.line_d_tangent * moved.tangent_covariance * moved.line_d_tangent.transpose();
  EXPECT_LT((moved_ambient - ambient).norm(), 1e-9 * ambient.norm());
  map.Move(new_from_old.Inverse());
  const ReferenceLineMap::Line& back = *map.Find(7);
  EXPECT_LT((back.line.direction - line.line.direction).norm(), 1e-12);
  EXPECT_LT((back.line.moment - line.line.moment).norm(), 1e-12);
  EXPECT_LT((back.tangent_covariance - line.tangent_covariance).norm(), 1e-9 * line.tangent_covariance.norm());
}

TEST(ReferenceLineMap, KeepsALineForMaxAgeReferencePairs) {
  for (const int max_age : {0, 2}) {
    ReferenceLineMap map(max_age);
    map.Keep(1, MapLine(kP, kQ));
    for (int pair = 1; pair <= 3; ++pair) {
      map.Age();
      EXPECT_EQ(map.Find(1) != nullptr, pair <= max_age) << "max_age " << max_age << ", pair " << pair;
    }
  }
  // Kept again: young again.
  ReferenceLineMap map(1);
  map.Keep(1, MapLine(kP, kQ));
  map.Age();
  map.Keep(1, MapLine(kP, kQ));
  map.Age();
  EXPECT_NE(map.Find(1), nullptr);
}

TEST(ReferenceLineMap, FindsTheLineASegmentPairProjectsFrom) {
  const StereoRig rig;
  ReferenceLineMap map(3);
  map.Reset(rig);
  const auto none = [](std::int64_t) { return false; };
  const auto is4 = [](std::int64_t id) { return id == 4; };
  map.Keep(4, MapLine(kP, kQ));
  map.Keep(9, MapLine(kP + Eigen::Vector3d(0.2, 0.0, 0.0), kQ + Eigen::Vector3d(0.2, 0.0, 0.0)));
  // A shorter piece of line 4, seen again.
  const Eigen::Vector3d p = kP + 0.2 * (kQ - kP), q = kP + 0.7 * (kQ - kP);
  const Segment2d left = Projected(rig, 0, p, q), right = Projected(rig, 1, p, q);
  std::int64_t id = -1;
  ASSERT_TRUE(map.FindByProjection(left, right, 1.0, none, &id));
  EXPECT_EQ(id, 4);
  // Not when its id is the new pair's (it is found by id then), nor with the other orientation.
  EXPECT_FALSE(map.FindByProjection(left, right, 1.0, is4, &id));
  const Segment2d left_reversed(left[2], left[3], left[0], left[1]), right_reversed(right[2], right[3], right[0], right[1]);
  EXPECT_FALSE(map.FindByProjection(left_reversed, right_reversed, 1.0, none, &id));
  // An endpoint 0.6 px off the line in the right image: within 1 px, not within 0.5 px.
  const Eigen::Vector2d d = (right.tail<2>() - right.head<2>()).normalized();
  Segment2d right_off = right;
  right_off.tail<2>() += 0.6 * Eigen::Vector2d(-d.y(), d.x());
  EXPECT_TRUE(map.FindByProjection(left, right_off, 1.0, none, &id));
  EXPECT_FALSE(map.FindByProjection(left, right_off, 0.5, none, &id));
  EXPECT_EQ(map.size(), 2);
}

TEST(ReferenceLineMap, TakesTheNearestOfTwoAndDropsTheOtherAsItsDuplicate) {
  const StereoRig rig;
  ReferenceLineMap map(3);
  map.Reset(rig);
  const auto none = [](std::int64_t) { return false; };
  // The same line stored twice, once 1 mm off (about 0.2 px at 2.5 m).
  const Eigen::Vector3d off(0.0, 0.001, 0.0);
  map.Keep(2, MapLine(kP + off, kQ + off));
  map.Keep(5, MapLine(kP, kQ));
  map.Keep(8, MapLine(kP + Eigen::Vector3d(0.2, 0.0, 0.0), kQ + Eigen::Vector3d(0.2, 0.0, 0.0)));
  std::int64_t id = -1;
  ASSERT_TRUE(map.FindByProjection(Projected(rig, 0, kP, kQ), Projected(rig, 1, kP, kQ), 1.0, none, &id));
  EXPECT_EQ(id, 5);
  EXPECT_EQ(map.Find(2), nullptr);
  EXPECT_NE(map.Find(5), nullptr);
  EXPECT_NE(map.Find(8), nullptr);
}

}  // namespace
}  // namespace slt
