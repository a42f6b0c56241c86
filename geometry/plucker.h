// 3-D lines in Pluecker coordinates (moment n, direction d; n = p x d for any point p on the
// line) and the stereo line transfer written with them.
//
// A Pluecker line seen by a camera [I | 0] projects to the image line l = n (the normal of the
// plane through the centre and the line). This makes the trifocal transfer of the reference
// pair (l_1, l'_1) into a current view cheap: the tensor's transfer (eq. 16 with the current
// camera as first view) intersects the back-projected planes pi = [l_1; 0] and
// pi' = E^T [l'_1; 0] -- the Pluecker line L_ref = StereoPairLine(E, l_1, l'_1), computed once
// per reference -- and images it: l_t = moment of (cam_from_ref * L_ref).
// trifocal_test.cc checks this against the tensor form; docs/derivations.md derives it.
#pragma once

#include <Eigen/Core>

#include "geometry/rigid3.h"
#include "geometry/se3.h"

namespace slt {

struct PlueckerLine {
  Eigen::Vector3d moment;
  Eigen::Vector3d direction;
};

using Matrix63d = Eigen::Matrix<double, 6, 3>;
using Matrix64d = Eigen::Matrix<double, 6, 4>;

// The intersection of two planes: moment = a_{1:3} b_4 - a_4 b_{1:3} (the plane form of eq. 16,
// LineFromPlanePair) and direction = b_{1:3} x a_{1:3}. Jacobians are 6x4 ([moment; direction]).
PlueckerLine PlueckerFromPlanes(const Eigen::Vector4d& a, const Eigen::Vector4d& b,
                                Matrix64d* d_a = nullptr, Matrix64d* d_b = nullptr);

// The line in frame b: n_b = R n_a + [t]_x R d_a, d_b = R d_a. d_line is the 3x6 Jacobian of the
// moment with respect to [n_a; d_a].
PlueckerLine TransformPluecker(const Rigid3d& b_from_a, const PlueckerLine& line,
                               Matrix36d* moment_d_line = nullptr);

// The 3-D line of a stereo pair of image lines (normalised coordinates), in the left camera's
// frame, with the Jacobians of [n; d] with respect to the left and right lines (6x3 each) and
// the sine of the angle between the two back-projected planes (near 0 for lines in the
// epipolar plane, where the pair does not define the line).
PlueckerLine StereoPairLine(const Rigid3d& right_from_left, const Eigen::Vector3d& left_line,
                            const Eigen::Vector3d& right_line, Matrix63d* d_left = nullptr,
                            Matrix63d* d_right = nullptr, double* plane_sine = nullptr);

// D d l / d [v; w] for the image l = n of a line (n, m) given in a camera's frame, under the
// perturbation camera_from_ref <- Exp(d) camera_from_ref: the line moves as n += w x n + v x m,
// m += w x m, so row i is [(m x a_i)^T, (n x a_i)^T] for the rows a_i of D. Forms no 3x6 matrix:
// trackers need this product per line and per iteration.
template <int K>
Eigen::Matrix<double, K, 6> ImageLinePoseJacobianProduct(const Eigen::Matrix<double, K, 3>& d,
                                                         const PlueckerLine& line_in_camera) {
  Eigen::Matrix<double, K, 6> out;
  for (int i = 0; i < K; ++i) {
    const Eigen::Vector3d a = d.row(i).transpose();
    out.template block<1, 3>(i, 0) = line_in_camera.direction.cross(a).transpose();
    out.template block<1, 3>(i, 3) = line_in_camera.moment.cross(a).transpose();
  }
  return out;
}

// D d l / d [n_ref; d_ref] for the image l in camera_from_ref of a reference-frame line:
// d l / d [n; d] = [R, [t]_x R], so D d l / d [n; d] = [D R, (D [t]_x) R].
template <int K>
Eigen::Matrix<double, K, 6> ImageLineLineJacobianProduct(const Eigen::Matrix<double, K, 3>& d,
                                                         const Rigid3d& camera_from_ref) {
  Eigen::Matrix<double, K, 6> out;
  Eigen::Matrix<double, K, 3> d_t;  // D [t]_x: a^T [t]_x = (a x t)^T
  for (int i = 0; i < K; ++i) d_t.row(i) = d.row(i).transpose().cross(camera_from_ref.translation).transpose();
  out.template leftCols<3>().noalias() = d * camera_from_ref.rotation;
  out.template rightCols<3>().noalias() = d_t * camera_from_ref.rotation;
  return out;
}

// The images of a reference-frame line in the current left camera (cam_from_ref) and right
// camera (right_from_left * cam_from_ref): normalised image lines, with the Jacobians with
// respect to the pose perturbation cam_from_ref <- Exp(d) cam_from_ref and, when asked, to the
// line [n; d]. (The full matrices, for tests and tools; trackers use the products above.)
struct StereoLineImages {
  Eigen::Vector3d left;
  Eigen::Vector3d right;
  Matrix36d left_d_pose;
  Matrix36d right_d_pose;
  Matrix36d left_d_line;
  Matrix36d right_d_line;
};
void ImageLineInStereoPair(const Rigid3d& right_from_left, const Rigid3d& cam_from_ref,
                           const PlueckerLine& line_in_ref, bool with_line_jacobians,
                           StereoLineImages* out);

}  // namespace slt
