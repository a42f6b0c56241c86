// The refined lines of earlier reference pairs, kept for the reference pairs after them (beyond
// the paper, whose Sec. 3.3 starts each reference pair from its own stereo pair).
//
// The reference refinement (reference_refinement.h) estimates each reference line L_i from the
// reference pair and its keyframes, with the covariance C_i of its 4-dof tangent. When the
// tracker takes a new reference pair at a frame whose pose M = new_from_old relative to the old
// reference is known, a line the two pairs share is carried into the new one as a prior
// (carry_over):
//     L_new = M L_old,   C_new = B_new^+ A(M) B_old C_old B_old^T A(M)^T B_new^+T,
// with A(M) = [R, [t]x R; 0, R] the 6x6 map of [n; d] (TransformPluecker; geometry/se3.h's
// Adjoint), B the tangent bases
// (optim/line_sfm_manifolds.h LineTangentBasis) and B^+ their left pseudo-inverses. Because
// both the prior and the new pair's pose come from the old reference, such a line ties the new
// reference to the old one's world frame: the poses measured against it do not inherit the new
// pair's placement error, which a chain of reference pairs otherwise accumulates.
//
// This map holds those lines in the current reference's frame, by the feature id they had when
// last refined, and moves them with every new reference pair (Move), so that a line is carried
// not only from the previous pair but from any of the last max_age pairs that refined it: a
// line leaving the view and coming back. A front end that lost a line gives it a new id when it
// detects it again; FindByProjection finds the map line a new reference line is by geometry:
// the map line whose projection into the new pair (K^-T n in the left image, the same of
// right_from_left L in the right) passes within max_px of both endpoints of its segment in both
// images, with the same orientation (the sign of the projected line's normal). With several
// such map lines (the same line stored under two ids), the nearest one (the smallest largest
// endpoint distance) is taken and the others are dropped as its duplicates.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <map>
#include <vector>

#include "geometry/camera.h"
#include "geometry/line2d.h"
#include "geometry/plucker.h"
#include "geometry/rigid3.h"

namespace slt {

class ReferenceLineMap {
 public:
  // A refined line in the current reference's frame: the line, its tangent basis B (at the
  // line) and the covariance of its tangent.
  struct Line {
    PlueckerLine line;
    Eigen::Matrix<double, 6, 4> line_d_tangent;
    Eigen::Matrix4d tangent_covariance;
  };

  // Lines not refined again for more than max_age reference pairs are dropped (0: only the
  // previous pair's lines are kept, the refinement's plain carry_over).
  explicit ReferenceLineMap(int max_age = 0) : max_age_(max_age) {}

  // A new sequence with this rig (for FindByProjection): no lines.
  void Reset(const StereoRig& rig);
  void Clear() { lines_.clear(); }
  // A new reference pair starts: every line ages by one pair, and those past max_age go.
  void Age();
  // The current reference's refined line `id` (before Move): replaces what the map held.
  void Keep(std::int64_t id, const Line& line);
  // Every line into the new reference's frame, new_from_old the new pair's pose relative to
  // the old reference: L = M L, its tangent covariance as above, B the basis at the moved line
  // (whose direction LineToParameters makes unit). A line without a direction is dropped.
  void Move(const Rigid3d& new_from_old);

  // The line stored as `id`, or null.
  const Line* Find(std::int64_t id) const;
  // The id of the map line that the stereo line (left, right) is, by the projection test
  // above into the rig of Reset, among the lines for whose id `excluded` is false: false when
  // none passes. Drops the duplicates of the one found.
  bool FindByProjection(const Segment2d& left, const Segment2d& right, double max_px,
                        const std::function<bool(std::int64_t)>& excluded, std::int64_t* id);
  void Erase(std::int64_t id) { lines_.erase(id); }
  int size() const { return static_cast<int>(lines_.size()); }

 private:
  struct Entry {
    Line line;
    int age = 0;
    Eigen::Vector3d projected[2];  // the line in the left and right image (pixels), for FindByProjection
  };
  // Projects the entry's line into both images (Keep and Move: once per line and reference pair).
  void Project(Entry* entry) const;
  int max_age_;
  Eigen::Matrix3d pixel_from_normalized_[2] = {Eigen::Matrix3d::Identity(), Eigen::Matrix3d::Identity()};
  Rigid3d right_from_left_;
  std::map<std::int64_t, Entry> lines_;
  std::vector<std::int64_t> duplicates_;  // scratch of FindByProjection
};

}  // namespace slt
