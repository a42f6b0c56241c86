// Rigid transformations of 3-D space.
//
// Naming follows the frames a transform maps between: `cam_from_world` maps a point given in
// world coordinates into camera coordinates, X_cam = cam_from_world * X_world. The paper's M_t
// is `cam_from_world` of the left camera at time t (eq. 1-2). See docs/conventions.md.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace slt {

using Matrix34d = Eigen::Matrix<double, 3, 4>;

struct Rigid3d {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Rigid3d() = default;
  Rigid3d(const Eigen::Matrix3d& r, const Eigen::Vector3d& t) : rotation(r), translation(t) {}

  static Rigid3d Identity() { return Rigid3d(); }
  bool AllFinite() const { return rotation.allFinite() && translation.allFinite(); }
  // From a unit quaternion (any sign) and a translation.
  static Rigid3d FromQuaternion(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) {
    return Rigid3d(q.normalized().toRotationMatrix(), t);
  }

  Eigen::Vector3d operator*(const Eigen::Vector3d& point) const {
    return rotation * point + translation;
  }
  // Composition: (c_from_b * b_from_a) = c_from_a.
  Rigid3d operator*(const Rigid3d& other) const {
    return Rigid3d(rotation * other.rotation, rotation * other.translation + translation);
  }
  Rigid3d Inverse() const {
    const Eigen::Matrix3d rt = rotation.transpose();
    return Rigid3d(rt, -(rt * translation));
  }
  // [R | t], the 3x4 camera matrix in normalised coordinates.
  Matrix34d ToMatrix3x4() const {
    Matrix34d m;
    m.leftCols<3>() = rotation;
    m.col(3) = translation;
    return m;
  }
  Eigen::Matrix4d ToMatrix4() const {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.topLeftCorner<3, 3>() = rotation;
    m.topRightCorner<3, 1>() = translation;
    return m;
  }
  Eigen::Quaterniond Quaternion() const { return Eigen::Quaterniond(rotation).normalized(); }
  // Position of the origin of the source frame expressed in the target frame's inverse, i.e.
  // for cam_from_world this is the camera centre in world coordinates.
  Eigen::Vector3d Center() const { return -(rotation.transpose() * translation); }
};

}  // namespace slt
