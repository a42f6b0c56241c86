#include "methods/elqursh_three_line/three_line_solver.h"

#include <Eigen/Geometry>
#include <cmath>

namespace slt {

const char* PrimitiveConfigurationStatusName(PrimitiveConfigurationStatus status) {
  switch (status) {
    case PrimitiveConfigurationStatus::kValid: return "valid";
    case PrimitiveConfigurationStatus::kParallelLinesCoincide: return "parallel lines coincide";
    case PrimitiveConfigurationStatus::kOrthogonalThroughVanishingPoint:
      return "orthogonal line through the vanishing point";
    case PrimitiveConfigurationStatus::kOrthogonalDirectionUndetermined:
      return "orthogonal line direction undetermined";
  }
  return "unknown";
}

PrimitiveConfigurationStatus PrimitiveConfigurationFrame(const PrimitiveConfigurationLines& lines,
                                                         double min_sine, Eigen::Matrix3d* frame) {
  const Eigen::Vector3d vanishing = lines.parallel1.cross(lines.parallel2);
  const double vanishing_norm = vanishing.norm();
  // Written as a product so that zero lines (and NaN) fail the test too.
  if (!(vanishing_norm >= min_sine * lines.parallel1.norm() * lines.parallel2.norm()) || vanishing_norm == 0.0) {
    return PrimitiveConfigurationStatus::kParallelLinesCoincide;
  }
  const Eigen::Vector3d d1 = vanishing / vanishing_norm;
  const double n3_norm = lines.orthogonal.norm();
  if (!(n3_norm > 0.0)) return PrimitiveConfigurationStatus::kOrthogonalDirectionUndetermined;
  const Eigen::Vector3d n3 = lines.orthogonal / n3_norm;
  if (!(std::abs(n3.dot(d1)) >= min_sine)) return PrimitiveConfigurationStatus::kOrthogonalThroughVanishingPoint;
  const Eigen::Vector3d across = n3.cross(d1);
  const double across_norm = across.norm();
  if (!(across_norm >= min_sine)) return PrimitiveConfigurationStatus::kOrthogonalDirectionUndetermined;
  const Eigen::Vector3d d2 = across / across_norm;
  frame->col(0) = d1;
  frame->col(1) = d2;
  frame->col(2) = d1.cross(d2);
  return PrimitiveConfigurationStatus::kValid;
}

PrimitiveConfigurationStatus RotationFromPrimitiveConfiguration(const PrimitiveConfigurationLines& in_a,
                                                                const PrimitiveConfigurationLines& in_b,
                                                                double min_sine, RotationCandidates* out) {
  out->count = 0;
  Eigen::Matrix3d frame_a, frame_b;
  PrimitiveConfigurationStatus status = PrimitiveConfigurationFrame(in_a, min_sine, &frame_a);
  if (status != PrimitiveConfigurationStatus::kValid) return status;
  status = PrimitiveConfigurationFrame(in_b, min_sine, &frame_b);
  if (status != PrimitiveConfigurationStatus::kValid) return status;
  // F_b S F_a^T for the four sign choices S = diag(s1, s2, s1 s2): flipping column i of F_b.
  const Eigen::Matrix3d frame_a_t = frame_a.transpose();
  static constexpr double kSigns[4][2] = {{1.0, 1.0}, {-1.0, 1.0}, {1.0, -1.0}, {-1.0, -1.0}};
  for (const auto& s : kSigns) {
    Eigen::Matrix3d signed_b;
    signed_b.col(0) = s[0] * frame_b.col(0);
    signed_b.col(1) = s[1] * frame_b.col(1);
    signed_b.col(2) = (s[0] * s[1]) * frame_b.col(2);
    out->b_from_a[out->count++].noalias() = signed_b * frame_a_t;
  }
  return PrimitiveConfigurationStatus::kValid;
}

bool TranslationFromStereoLines(const Eigen::Matrix3d& b_from_a_rotation, const Rigid3d& right_from_left,
                                const StereoLineConstraint* lines, int count, double min_eigenvalue_ratio,
                                Eigen::Vector3d* b_from_a_translation) {
  // Normal equations of the rows  n^T t = -n^T R X  and  (E_R^T n')^T t = -n'^T (E_R R X + E_t).
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  const Eigen::Matrix3d& rig_rotation = right_from_left.rotation;
  for (int i = 0; i < count; ++i) {
    const StereoLineConstraint& line = lines[i];
    const Eigen::Vector3d rotated = b_from_a_rotation * line.point_in_a;
    const Eigen::Vector3d& n = line.left_normal;
    const Eigen::Vector3d n_right = rig_rotation.transpose() * line.right_normal;
    const double b_left = -n.dot(rotated);
    const double b_right = -n_right.dot(rotated) - line.right_normal.dot(right_from_left.translation);
    normal.noalias() += n * n.transpose() + n_right * n_right.transpose();
    rhs += b_left * n + b_right * n_right;
  }
  // Accepting det >= r tr^3 / 4 guarantees lambda_min >= r lambda_max: lambda_1 lambda_2 <=
  // (tr / 2)^2, so lambda_min >= 4 det / tr^2 >= r tr >= r lambda_max (cheaper than the
  // eigenvalues, and conservative by at most a factor 27 / 4).
  const double trace = normal.trace();
  const double det = normal.determinant();
  if (!(trace > 0.0) || !(det >= 0.25 * min_eigenvalue_ratio * trace * trace * trace)) return false;
  // A^T A t = A^T b by the adjugate: A^T A is symmetric and well conditioned here.
  Eigen::Matrix3d adjugate;
  adjugate.col(0) = normal.col(1).cross(normal.col(2));
  adjugate.col(1) = normal.col(2).cross(normal.col(0));
  adjugate.col(2) = normal.col(0).cross(normal.col(1));
  const Eigen::Vector3d t = adjugate.transpose() * rhs / det;
  if (!t.allFinite()) return false;
  *b_from_a_translation = t;
  return true;
}

}  // namespace slt
