// Central-difference Jacobians, used by the tests of every analytic derivative in the project.
#pragma once

#include <Eigen/Core>

namespace slt {

// J(:, i) = (f(x + h e_i) - f(x - h e_i)) / 2h for a function of a fixed-size vector.
template <int OutDim, int InDim, typename Function>
Eigen::Matrix<double, OutDim, InDim> CentralDifferenceJacobian(
    const Function& f, const Eigen::Matrix<double, InDim, 1>& x, double step = 1e-6) {
  Eigen::Matrix<double, OutDim, InDim> jacobian;
  for (int i = 0; i < InDim; ++i) {
    Eigen::Matrix<double, InDim, 1> plus = x, minus = x;
    plus(i) += step;
    minus(i) -= step;
    jacobian.col(i) = (f(plus) - f(minus)) / (2.0 * step);
  }
  return jacobian;
}

}  // namespace slt
