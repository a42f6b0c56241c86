#include "optim/line_pose_marginals.h"

#include <Eigen/Cholesky>

namespace slt {

bool LineMarginalCovariances(const std::vector<Eigen::Matrix4d>& a, const Eigen::MatrixXd& b,
                             const std::vector<Matrix6d>& d, std::vector<Eigen::Matrix4d>* covariances, int pose,
                             Matrix6d* pose_covariance) {
  const Eigen::Index rows = 4 * static_cast<Eigen::Index>(a.size());
  if (b.rows() != rows || b.cols() != 6 * static_cast<Eigen::Index>(d.size())) return false;
  Eigen::MatrixXd reduced = Eigen::MatrixXd::Zero(rows, rows);
  Eigen::Matrix<double, 6, Eigen::Dynamic> d_inverse_bt(6, rows);
  for (size_t k = 0; k < d.size(); ++k) {
    const Eigen::LLT<Matrix6d> llt(d[k]);  // fails on a zero pivot, unlike LDLT's isPositive
    if (llt.info() != Eigen::Success) return false;
    const auto b_k = b.middleCols<6>(6 * static_cast<Eigen::Index>(k));
    d_inverse_bt = llt.solve(b_k.transpose());
    reduced.noalias() -= b_k * d_inverse_bt;
  }
  for (size_t i = 0; i < a.size(); ++i) reduced.block<4, 4>(4 * static_cast<Eigen::Index>(i), 4 * static_cast<Eigen::Index>(i)) += a[i];
  const Eigen::LLT<Eigen::MatrixXd> llt(reduced);
  if (llt.info() != Eigen::Success) return false;
  const Eigen::MatrixXd inverse = llt.solve(Eigen::MatrixXd::Identity(rows, rows));
  covariances->resize(a.size());
  for (size_t i = 0; i < a.size(); ++i) {
    (*covariances)[i] = inverse.block<4, 4>(4 * static_cast<Eigen::Index>(i), 4 * static_cast<Eigen::Index>(i));
  }
  if (pose_covariance != nullptr && pose >= 0 && pose < static_cast<int>(d.size())) {
    const Eigen::LLT<Matrix6d> d_llt(d[static_cast<size_t>(pose)]);
    const Matrix6d d_inverse = d_llt.solve(Matrix6d::Identity());
    const Eigen::MatrixXd b_d_inverse = b.middleCols<6>(6 * static_cast<Eigen::Index>(pose)) * d_inverse;
    *pose_covariance = d_inverse + b_d_inverse.transpose() * inverse * b_d_inverse;
  }
  return true;
}

}  // namespace slt
