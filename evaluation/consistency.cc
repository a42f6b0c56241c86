#include "evaluation/consistency.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/chi_square.h"
#include "common/csv.h"

namespace slt {
namespace {

// x^T A^-1 x through a Cholesky factor; false when A is not positive definite.
template <int N>
bool Mahalanobis(const Eigen::Matrix<double, N, N>& a, const Eigen::Matrix<double, N, 1>& x, double* squared) {
  const Eigen::LLT<Eigen::Matrix<double, N, N>> llt(a);
  if (llt.info() != Eigen::Success) return false;
  *squared = x.dot(llt.solve(x));
  return std::isfinite(*squared);
}

}  // namespace

ConsistencyErrors EvaluateConsistency(const Trajectory& gt, const Trajectory& est,
                                      const std::vector<Matrix6d>& covariances, double max_time_diff_s) {
  if (covariances.size() != est.size()) {
    throw std::invalid_argument("consistency: " + std::to_string(covariances.size()) + " covariances for " +
                                std::to_string(est.size()) + " estimated poses");
  }
  const std::vector<PosePair> pairs = AssociateByTime(gt, est, max_time_diff_s);
  ConsistencyErrors result;
  result.associated_poses = pairs.size();
  std::vector<double> nees, nees_rot, nees_pos;
  size_t axes = 0, beyond = 0;
  for (const PosePair& pair : pairs) {
    const Matrix6d& p = covariances[pair.est_index];
    const Rigid3d& world_from_est = est[pair.est_index].world_from_cam;
    const Rigid3d& world_from_gt = gt[pair.gt_index].world_from_cam;
    // d with true = Exp(d) * estimate, both as cam_from_world.
    const Vector6d d = LogSE3(world_from_gt.Inverse() * world_from_est);
    const Eigen::Vector3d e_rot = d.tail<3>();
    const Eigen::Vector3d e_pos = world_from_gt.translation - world_from_est.translation;
    const Eigen::Matrix3d& r = world_from_est.rotation;  // world_from_cam: P_c = R P_vv R^T
    const Eigen::Matrix3d p_rot = p.bottomRightCorner<3, 3>();
    const Eigen::Matrix3d p_pos = r * p.topLeftCorner<3, 3>() * r.transpose();
    double q = 0.0, q_rot = 0.0, q_pos = 0.0;
    if (!Mahalanobis<6>(p, d, &q) || !Mahalanobis<3>(p_rot, e_rot, &q_rot) || !Mahalanobis<3>(p_pos, e_pos, &q_pos)) {
      continue;
    }
    nees.push_back(q);
    nees_rot.push_back(q_rot);
    nees_pos.push_back(q_pos);
    for (int i = 0; i < 3; ++i) {
      beyond += std::abs(e_rot(i)) > 3.0 * std::sqrt(p_rot(i, i));
      beyond += std::abs(e_pos(i)) > 3.0 * std::sqrt(p_pos(i, i));
    }
    axes += 6;
  }
  if (nees.empty()) throw std::invalid_argument("consistency: no associated pose has a positive-definite covariance");
  result.used_poses = nees.size();
  result.per_frame_nees = nees;
  result.nees = ComputeStatistics(std::move(nees));
  result.nees_rot = ComputeStatistics(std::move(nees_rot));
  result.nees_pos = ComputeStatistics(std::move(nees_pos));
  result.beyond_3sigma_fraction = static_cast<double>(beyond) / static_cast<double>(axes);
  return result;
}

std::pair<double, double> NeesBand(double probability, int dof, int trials) {
  if (!(probability > 0.0 && probability < 1.0) || dof < 1 || trials < 1) {
    throw std::invalid_argument("NeesBand: need 0 < probability < 1, dof >= 1, trials >= 1");
  }
  const double tail = 0.5 * (1.0 - probability);
  const int k = dof * trials;
  return {ChiSquareQuantile(tail, k) / trials, ChiSquareQuantile(1.0 - tail, k) / trials};
}

nlohmann::json ToJson(const ConsistencyErrors& c) {
  return {{"associated_poses", c.associated_poses},
          {"used_poses", c.used_poses},
          {"nees", ToJson(c.nees)},
          {"nees_rot", ToJson(c.nees_rot)},
          {"nees_pos", ToJson(c.nees_pos)},
          {"beyond_3sigma_pct", 100.0 * c.beyond_3sigma_fraction}};
}

std::vector<Matrix6d> ReadLogCovariances(const std::string& path) {
  const CsvTable table = ReadCsvFile(path);
  size_t columns[6][6];
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) columns[i][j] = columns[j][i] = table.Column("cov_" + std::to_string(i) + std::to_string(j));
  }
  std::vector<Matrix6d> covariances;
  covariances.reserve(table.rows.size());
  for (size_t r = 0; r < table.rows.size(); ++r) {
    Matrix6d p = Matrix6d::Zero();
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 6; ++j) {
        const std::string& field = table.rows[r][columns[i][j]];
        if (field.empty()) continue;
        try {
          p(i, j) = ParseDouble(field);
        } catch (const std::invalid_argument&) {
          throw std::runtime_error(path + ": row " + std::to_string(r + 1) + ", column cov_" +
                                   std::to_string(std::min(i, j)) + std::to_string(std::max(i, j)) +
                                   ": not a number: '" + field + "'");
        }
      }
    }
    covariances.push_back(p);
  }
  return covariances;
}

}  // namespace slt
