// Trifocal tensors for three views with the first camera at [I | 0] (paper eq. 16-17), and the
// same transfers evaluated through back-projected planes, with their Jacobians with respect to
// a pose twist.
//
// Tensor form (Hartley & Zisserman, Sec. 15.1): for cameras P1 = [I | 0], P2 = A = [a_1 .. a_4],
// P3 = B = [b_1 .. b_4] (a_i, b_i columns),
//   T_i = a_i b_4^T - a_4 b_i^T                       (eq. 17)
//   line transfer into view 1:  l_i = l'^T T_i l''     (eq. 16)
//   point transfer into view 3: x''^k = x^i l'_j T_i^{jk}, l' a line through x' in view 2.
//
// Plane form, used by the trackers because it costs a fraction of forming 27 entries: with
// pi' = A^T l' and pi'' = B^T l'' the planes back-projected from views 2 and 3,
//   l = pi'_{1:3} pi''_4 - pi'_4 pi''_{1:3},
// which is the image in view 1 of the 3-D line pi' ^ pi''; it is term for term eq. 16.
//
// (The other direction, the reference pair into the current pair, is the Pluecker form of
// plucker.h.) Pose perturbations are on the left and in the camera frame: cam_from_ref <- Exp(d) cam_from_ref,
// d = [v; w] (se3.h). Every Jacobian here is tested against central differences.
#pragma once

#include <Eigen/Core>
#include <array>

#include "geometry/rigid3.h"
#include "geometry/se3.h"

namespace slt {


struct TrifocalTensor {
  // slices[i](j, k) = T_i^{jk}.
  std::array<Eigen::Matrix3d, 3> slices;
};

// Eq. 17 for P1 = [I | 0], P2 = A, P3 = B.
TrifocalTensor TrifocalTensorFromCameras(const Matrix34d& A, const Matrix34d& B);
// Eq. 16: the line in view 1 from a line in view 2 and a line in view 3.
Eigen::Vector3d TransferLine(const TrifocalTensor& tensor, const Eigen::Vector3d& line2,
                             const Eigen::Vector3d& line3);
// The point in view 3 from a point in view 1 and a line through its match in view 2.
Eigen::Vector3d TransferPoint(const TrifocalTensor& tensor, const Eigen::Vector3d& point1,
                              const Eigen::Vector3d& line2);

// The line through `point` perpendicular to `epipolar_line` (both in the same image). Point
// transfer needs a line through x' other than the epipolar line of x, on which it vanishes;
// the perpendicular is the best-conditioned choice.
Eigen::Vector3d PerpendicularLineThroughPoint(const Eigen::Vector3d& epipolar_line,
                                              const Eigen::Vector2d& point);

// Sine of the angle between the normals of two planes.
double PlaneAngleSine(const Eigen::Vector4d& a, const Eigen::Vector4d& b);

// The image in view [I | 0] of the intersection of two planes; the plane form of eq. 16.
// Jacobians are with respect to each plane.
Eigen::Vector3d LineFromPlanePair(const Eigen::Vector4d& plane2, const Eigen::Vector4d& plane3,
                                  Eigen::Matrix<double, 3, 4>* d_plane2 = nullptr,
                                  Eigen::Matrix<double, 3, 4>* d_plane3 = nullptr);

// A plane given in the current camera's frame, expressed in the reference frame:
// pi_ref = M^T pi_cam with M = cam_from_ref (4x4). d_delta: Jacobian under
// cam_from_ref <- Exp(d) cam_from_ref at d = 0.
Eigen::Vector4d PlaneToReference(const Rigid3d& cam_from_ref, const Eigen::Vector4d& plane_in_cam,
                                 Matrix46d* d_delta = nullptr);
// The 3-D point (homogeneous) where the ray of x1 (view [I | 0], normalised coordinates)
// meets a plane; the plane form of point transfer.
Eigen::Vector4d IntersectRayWithPlane(const Eigen::Vector3d& point1, const Eigen::Vector4d& plane);

// The two transfers of the paper's Fig. 3 for one line (normalised coordinates), with the
// stereo rig E = right_from_left and the current left camera M = cam_from_ref:
//   via_T      : T  over (I_1, I'_1, I_t) transfers (l'_1, l_t)  into I_1,
//   via_Tprime : T' over (I_1, I_t, I'_t) transfers (l_t, l'_t)  into I_1.
// Jacobians with respect to the pose and to each input line (3x3 blocks), when asked for.
struct CurrentToReferenceTransfer {
  Eigen::Vector3d via_T;
  Eigen::Vector3d via_Tprime;
  // Sine of the angle between the two back-projected planes each transfer intersects: near
  // zero the line lies in the epipolar plane of those two views and the transfer degenerates.
  double via_T_plane_sine;
  double via_Tprime_plane_sine;
  Matrix36d via_T_d_pose;
  Matrix36d via_Tprime_d_pose;
  Eigen::Matrix3d via_T_d_ref_right;
  Eigen::Matrix3d via_T_d_cur_left;
  Eigen::Matrix3d via_Tprime_d_cur_left;
  Eigen::Matrix3d via_Tprime_d_cur_right;
};
void TransferCurrentToReference(const Rigid3d& right_from_left, const Rigid3d& cam_from_ref,
                                const Eigen::Vector3d& ref_right, const Eigen::Vector3d& cur_left,
                                const Eigen::Vector3d& cur_right, bool with_jacobians,
                                CurrentToReferenceTransfer* out);

}  // namespace slt
