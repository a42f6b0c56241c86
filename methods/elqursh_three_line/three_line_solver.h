// The minimal solvers of the Elqursh & Elgammal baseline (method `elqursh_three_line`):
// A. Elqursh and A. Elgammal, "Line-based relative pose estimation", CVPR 2011.
//
// Rotation from a primitive configuration (their Sec. 3): three 3-D lines L1, L2, L3 with L1
// parallel to L2 (direction D1) and L3 orthogonal to them (direction D2, D1 . D2 = 0), seen in
// two views a and b. In each view, with the normalised image lines l = K^T l_px (the normals of
// the planes through the camera centre and the lines, docs/conventions.md):
//   d1 ~ v = l1 x l2             the vanishing point of L1, L2: D1 in the camera's frame;
//   d2 ~ n3 x d1, n3 = l3        L3 lies in the plane of l3 (n3 . D2 = 0) and D2 . D1 = 0;
//   F  = [d1, d2, d1 x d2]       (unit columns) = R_cam D, D = [D1, D2, D1 x D2].
// The paper writes d2 as the vanishing point l3 x (omega v) of L3, omega the image of the
// absolute conic; in normalised coordinates omega = I and it is the same vector. Then
//   b_from_a = F_b S F_a^T,  S in {diag(1, 1, 1), diag(-1, 1, -1), diag(1, -1, -1), diag(-1, -1, 1)},
// four candidates because d1 and d2 are known up to sign in each view; all four are returned and
// the consensus of the other lines picks one (the paper resolves the ambiguity the same way).
//
// A view is rejected (no candidate, a reason reported) when
//   - l1 ~ l2: the sine of the angle between the two planes is below min_sine, so v is not
//     defined (the same image line, or far lines seen from nearly the same plane);
//   - l3 passes through v: |n3 . d1| < min_sine. The plane of L3 then contains D1; in this view
//     L3 cannot be told from a third line parallel to L1 and L2, for which n3 x d1 is a
//     viewpoint-dependent direction and the rotation would be wrong. (Rejecting it also keeps the
//     translation below determined: the plane normals of L1, L2 are orthogonal to D1, n3 is not.)
//   - l3 is the vanishing line of the planes orthogonal to D1: |n3 x d1| < min_sine, d2 is not
//     defined.
//
// Metric translation with the stereo rig (this project's extension; Elqursh's method is
// monocular and recovers t up to scale from line junctions): a line triangulated in the stereo
// pair of view a (geometry/plucker.h StereoPairLine) has a point X (in a's left camera frame)
// that lies, in view b, in the back-projected plane n of its image in the left camera and n' in
// the right camera (E = right_from_left):
//   n^T (R X + t) = 0,        n'^T (E_R (R X + t) + E_t) = 0,
// i.e. two equations linear in t per line, rows n^T and (E_R^T n')^T. Lines of one direction D
// give normals orthogonal to D (in a rectified rig), so three lines not all parallel fix t; the
// least-squares solution of all rows is returned. Each row is weighted by the scale of its
// normal: scaled to a unit image normal over the point's depth, a row's residual is the image
// distance (normalised coordinates) of the projected point from the observed line.
#pragma once

#include <Eigen/Core>
#include <array>

#include "geometry/rigid3.h"

namespace slt {

// The normalised image lines (K^T l) of a primitive configuration in one view.
struct PrimitiveConfigurationLines {
  Eigen::Vector3d parallel1;
  Eigen::Vector3d parallel2;
  Eigen::Vector3d orthogonal;
};

enum class PrimitiveConfigurationStatus {
  kValid,
  kParallelLinesCoincide,             // l1 ~ l2: no vanishing point
  kOrthogonalThroughVanishingPoint,   // l3 passes through v: could be a third parallel line
  kOrthogonalDirectionUndetermined,   // l3 is the vanishing line of the planes orthogonal to d1
};
const char* PrimitiveConfigurationStatusName(PrimitiveConfigurationStatus status);

// The frame F = [d1, d2, d1 x d2] of one view (orthonormal, det +1) when the view is valid.
PrimitiveConfigurationStatus PrimitiveConfigurationFrame(const PrimitiveConfigurationLines& lines,
                                                         double min_sine, Eigen::Matrix3d* frame);

struct RotationCandidates {
  int count = 0;  // 0 (a view was rejected) or 4
  std::array<Eigen::Matrix3d, 4> b_from_a;
};

// The rotations b_from_a consistent with the configuration seen in views a and b. The status
// is that of the first rejected view (kValid when count = 4).
PrimitiveConfigurationStatus RotationFromPrimitiveConfiguration(const PrimitiveConfigurationLines& in_a,
                                                                const PrimitiveConfigurationLines& in_b,
                                                                double min_sine, RotationCandidates* out);

// One stereo line for the translation: a point on the 3-D line in a's left camera frame and
// the back-projected plane normals of its images in view b's left and right cameras (each
// scaled as the weight of its row, see above).
struct StereoLineConstraint {
  Eigen::Vector3d point_in_a;
  Eigen::Vector3d left_normal;
  Eigen::Vector3d right_normal;
};

// Least-squares t of b_from_a = [R | t] from `count` lines (two rows each). Returns false, t
// unchanged, when the rows do not fix t (e.g. all lines parallel): det(A^T A) below
// min_eigenvalue_ratio * trace(A^T A)^3 / 4, a test that accepts only when the smallest
// eigenvalue of A^T A is at least min_eigenvalue_ratio times the largest.
bool TranslationFromStereoLines(const Eigen::Matrix3d& b_from_a_rotation, const Rigid3d& right_from_left,
                                const StereoLineConstraint* lines, int count, double min_eigenvalue_ratio,
                                Eigen::Vector3d* b_from_a_translation);

}  // namespace slt
