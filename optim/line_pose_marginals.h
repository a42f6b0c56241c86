// Marginal covariances of the lines of a line bundle adjustment, by eliminating the poses.
//
// Each residual of the reference refinement (methods/trifocal_line_ekf/reference_refinement.h)
// sees one line and one pose, so its Gauss-Newton information is
//     H = [ A    B ]    A = diag(A_1 .. A_n)  (4 x 4: the lines' tangents),
//         [ B^T  D ]    D = diag(D_1 .. D_m)  (6 x 6: the poses' tangents),
// with B (4n x 6m) the line-pose blocks. The lines' block of H^-1 is the inverse of their
// reduced information (Schur complement of D):
//     C = (A - sum_k B_k D_k^-1 B_k^T)^-1,   B_k the 4n x 6 columns of pose k,
// cubic in the number of lines and linear in the poses; the other way round, through the
// poses' complement D - B^T A^-1 B, is cubic in the poses. Both give the same blocks up to
// rounding.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "geometry/se3.h"

namespace slt {

// Sets (*covariances)[i] to the 4 x 4 block of line i of H^-1 (above) from A's blocks `a`
// (n of them), B (4n x 6m, column block k for pose k) and D's blocks `d` (m of them). With
// `pose` in [0, m) and `pose_covariance` non-null, also sets *pose_covariance to pose k's block
// of H^-1 (its marginal covariance, the lines' uncertainty and all their correlations included):
//     D_k^-1 + D_k^-1 B_k^T C B_k D_k^-1.
// Returns false, leaving the outputs unspecified, when a D_k or the reduced information is not
// positive definite (a pose or a line direction the data do not determine).
bool LineMarginalCovariances(const std::vector<Eigen::Matrix4d>& a, const Eigen::MatrixXd& b,
                             const std::vector<Matrix6d>& d, std::vector<Eigen::Matrix4d>* covariances,
                             int pose = -1, Matrix6d* pose_covariance = nullptr);

}  // namespace slt
