#include "geometry/se3.h"

#include <Eigen/Geometry>
#include <cmath>

namespace slt {
namespace {

// Below this rotation angle the closed-form coefficients lose digits to cancellation and
// their Taylor series (three terms, truncation error ~theta^6) are used instead.
constexpr double kSeriesAngle = 1e-2;

struct SO3Coefficients {
  double sin_over;        // sin(t)/t
  double one_minus_cos;   // (1 - cos t)/t^2
  double t_minus_sin;     // (t - sin t)/t^3
};

SO3Coefficients Coefficients(double theta) {
  const double t2 = theta * theta;
  if (theta < kSeriesAngle) {
    return {1.0 - t2 / 6.0 + t2 * t2 / 120.0, 0.5 - t2 / 24.0 + t2 * t2 / 720.0,
            1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0};
  }
  const double s = std::sin(theta), c = std::cos(theta);
  return {s / theta, (1.0 - c) / t2, (theta - s) / (t2 * theta)};
}

Eigen::Matrix3d QMatrix(const Eigen::Vector3d& rho, const Eigen::Vector3d& phi) {
  // Barfoot eq. 7.86: the top-right block of the SE(3) left Jacobian.
  const double theta = phi.norm();
  const double t2 = theta * theta;
  double c1, c2, c3;
  if (theta < kSeriesAngle) {
    c1 = 1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0;
    c2 = 1.0 / 24.0 - t2 / 720.0 + t2 * t2 / 40320.0;
    c3 = 1.0 / 120.0 - t2 / 2520.0 + t2 * t2 / 120960.0;
  } else {
    const double s = std::sin(theta), c = std::cos(theta);
    c1 = (theta - s) / (t2 * theta);
    c2 = (t2 + 2.0 * c - 2.0) / (2.0 * t2 * t2);
    c3 = (2.0 * theta - 3.0 * s + theta * c) / (2.0 * t2 * t2 * theta);
  }
  const Eigen::Matrix3d P = Skew(phi), V = Skew(rho);
  const Eigen::Matrix3d PV = P * V, VP = V * P, PVP = PV * P;
  return 0.5 * V + c1 * (PV + VP + PVP) + c2 * (P * PV + VP * P - 3.0 * PVP) +
         c3 * (PVP * P + P * PVP);
}

}  // namespace

double RotationAngle(const Eigen::Matrix3d& rotation) {
  const Eigen::Vector3d axis_sin(rotation(2, 1) - rotation(1, 2), rotation(0, 2) - rotation(2, 0),
                                 rotation(1, 0) - rotation(0, 1));
  return std::atan2(0.5 * axis_sin.norm(), 0.5 * (rotation.trace() - 1.0));
}

Eigen::Matrix3d ExpSO3(const Eigen::Vector3d& w) {
  const SO3Coefficients k = Coefficients(w.norm());
  const Eigen::Matrix3d W = Skew(w);
  return Eigen::Matrix3d::Identity() + k.sin_over * W + k.one_minus_cos * W * W;
}

Eigen::Vector3d LogSO3(const Eigen::Matrix3d& rotation) {
  // Through the quaternion: accurate near 0 and near pi alike.
  const Eigen::AngleAxisd aa(Eigen::Quaterniond(rotation).normalized());
  return aa.angle() * aa.axis();
}

Eigen::Matrix3d LeftJacobianSO3(const Eigen::Vector3d& w) {
  const SO3Coefficients k = Coefficients(w.norm());
  const Eigen::Matrix3d W = Skew(w);
  return Eigen::Matrix3d::Identity() + k.one_minus_cos * W + k.t_minus_sin * W * W;
}

Eigen::Matrix3d LeftJacobianInverseSO3(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  const double t2 = theta * theta;
  double e;
  if (theta < kSeriesAngle) {
    e = 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0;
  } else {
    e = 1.0 / t2 - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta));
  }
  const Eigen::Matrix3d W = Skew(w);
  return Eigen::Matrix3d::Identity() - 0.5 * W + e * W * W;
}

Eigen::Matrix4d Hat(const Vector6d& xi) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m.topLeftCorner<3, 3>() = Skew(xi.tail<3>());
  m.topRightCorner<3, 1>() = xi.head<3>();
  return m;
}

Rigid3d ExpSE3(const Vector6d& xi) {
  const Eigen::Vector3d w = xi.tail<3>();
  return Rigid3d(ExpSO3(w), LeftJacobianSO3(w) * xi.head<3>());
}

Vector6d LogSE3(const Rigid3d& transform) {
  Vector6d xi;
  xi.tail<3>() = LogSO3(transform.rotation);
  xi.head<3>() = LeftJacobianInverseSO3(xi.tail<3>()) * transform.translation;
  return xi;
}

Rigid3d FirstOrderSE3(const Vector6d& xi) {
  // I + [w]_x projected onto SO(3) through its quaternion (exact to first order).
  const Eigen::Quaterniond q(1.0, 0.5 * xi(3), 0.5 * xi(4), 0.5 * xi(5));
  return Rigid3d(q.normalized().toRotationMatrix(), xi.head<3>());
}

Matrix6d Adjoint(const Rigid3d& transform) {
  Matrix6d ad = Matrix6d::Zero();
  ad.topLeftCorner<3, 3>() = transform.rotation;
  ad.bottomRightCorner<3, 3>() = transform.rotation;
  ad.topRightCorner<3, 3>() = Skew(transform.translation) * transform.rotation;
  return ad;
}

Matrix6d LeftJacobianSE3(const Vector6d& xi) {
  const Eigen::Matrix3d J = LeftJacobianSO3(xi.tail<3>());
  Matrix6d out = Matrix6d::Zero();
  out.topLeftCorner<3, 3>() = J;
  out.bottomRightCorner<3, 3>() = J;
  out.topRightCorner<3, 3>() = QMatrix(xi.head<3>(), xi.tail<3>());
  return out;
}

Matrix6d LeftJacobianSE3FirstOrder(const Vector6d& xi) {
  Matrix6d out = Matrix6d::Identity();
  const Eigen::Matrix3d half_w = 0.5 * Skew(xi.tail<3>());
  out.topLeftCorner<3, 3>() += half_w;
  out.bottomRightCorner<3, 3>() += half_w;
  out.topRightCorner<3, 3>() = 0.5 * Skew(xi.head<3>());
  return out;
}


}  // namespace slt
