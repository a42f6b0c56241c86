#include "geometry/line2d.h"

#include <cmath>

namespace slt {

Eigen::Vector3d LineThroughPoints(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                  Eigen::Matrix<double, 3, 4>* d_points) {
  // [ax ay 1] x [bx by 1] = (ay - by, bx - ax, ax by - ay bx)
  if (d_points) {
    *d_points << 0.0, 1.0, 0.0, -1.0,  //
        -1.0, 0.0, 1.0, 0.0,            //
        b.y(), -b.x(), -a.y(), a.x();
  }
  return {a.y() - b.y(), b.x() - a.x(), a.x() * b.y() - a.y() * b.x()};
}

Eigen::Vector3d NormalizedLineFromPixelLine(const PinholeCamera& camera, const Eigen::Vector3d& l) {
  return {camera.fx * l.x(), camera.fy * l.y(), camera.cx * l.x() + camera.cy * l.y() + l.z()};
}

Eigen::Matrix3d PixelFromNormalizedLineMatrix(const PinholeCamera& camera) {
  // K^-T for K = [fx 0 cx; 0 fy cy; 0 0 1].
  Eigen::Matrix3d m;
  m << 1.0 / camera.fx, 0.0, 0.0,  //
      0.0, 1.0 / camera.fy, 0.0,   //
      -camera.cx / camera.fx, -camera.cy / camera.fy, 1.0;
  return m;
}

Eigen::Vector3d PixelLineFromNormalizedLine(const PinholeCamera& camera, const Eigen::Vector3d& l) {
  const double a = l.x() / camera.fx, b = l.y() / camera.fy;
  return {a, b, l.z() - camera.cx * a - camera.cy * b};
}

Eigen::Vector3d UnitNormalLine(const Eigen::Vector3d& line) {
  return line / line.head<2>().norm();
}

double SignedDistance(const Eigen::Vector3d& line, const Eigen::Vector2d& point,
                      Eigen::Matrix<double, 1, 3>* d_line, Eigen::Matrix<double, 1, 2>* d_point) {
  const double inv_rho = 1.0 / line.head<2>().norm();
  const double d = (line.x() * point.x() + line.y() * point.y() + line.z()) * inv_rho;
  if (d_line) {
    const double k = d * inv_rho * inv_rho;
    *d_line << point.x() * inv_rho - k * line.x(), point.y() * inv_rho - k * line.y(), inv_rho;
  }
  if (d_point) *d_point << line.x() * inv_rho, line.y() * inv_rho;
  return d;
}

Eigen::Vector2d ThetaLambdaFromLine(const Eigen::Vector3d& line, Eigen::Matrix<double, 2, 3>* d_line) {
  const double a = line.x(), b = line.y(), c = line.z();
  const double rho2 = a * a + b * b;
  const double rho = std::sqrt(rho2);
  if (d_line) {
    const double k = c / (rho2 * rho);
    *d_line << -b / rho2, a / rho2, 0.0,  //
        k * a, k * b, -1.0 / rho;
  }
  return {std::atan2(b, a), -c / rho};
}

double WrapAngle(double angle) {
  angle = std::remainder(angle, 2.0 * M_PI);  // [-pi, pi]
  return angle <= -M_PI ? angle + 2.0 * M_PI : angle;
}

Eigen::Vector2d ThetaLambdaResidual(const Eigen::Vector3d& measured, const Eigen::Vector3d& predicted,
                                    Eigen::Matrix<double, 2, 3>* d_predicted) {
  const double sign = measured.head<2>().dot(predicted.head<2>()) < 0.0 ? -1.0 : 1.0;
  Eigen::Matrix<double, 2, 3> d_aligned;
  const Eigen::Vector2d tl_p = ThetaLambdaFromLine(sign * predicted, d_predicted ? &d_aligned : nullptr);
  const Eigen::Vector2d tl_m = ThetaLambdaFromLine(measured);
  if (d_predicted) *d_predicted = -sign * d_aligned;
  return {WrapAngle(tl_m.x() - tl_p.x()), tl_m.y() - tl_p.y()};
}

}  // namespace slt
