#include "methods/trifocal_line_ekf/reference_line_map.h"

#include <algorithm>
#include <cmath>

#include "geometry/se3.h"
#include "optim/line_sfm_manifolds.h"

namespace slt {

void ReferenceLineMap::Age() {
  for (auto it = lines_.begin(); it != lines_.end();) {
    it = ++it->second.age > max_age_ ? lines_.erase(it) : std::next(it);
  }
}

void ReferenceLineMap::Reset(const StereoRig& rig) {
  pixel_from_normalized_[0] = PixelFromNormalizedLineMatrix(rig.left);
  pixel_from_normalized_[1] = PixelFromNormalizedLineMatrix(rig.right);
  right_from_left_ = rig.right_from_left;
  lines_.clear();
}

void ReferenceLineMap::Project(Entry* entry) const {
  const PlueckerLine& line = entry->line.line;
  entry->projected[0] = pixel_from_normalized_[0] * line.moment;
  entry->projected[1] = pixel_from_normalized_[1] * TransformPluecker(right_from_left_, line).moment;
}

void ReferenceLineMap::Keep(std::int64_t id, const Line& line) {
  Entry& entry = lines_[id];
  entry.line = line;
  entry.age = 0;
  Project(&entry);
}

void ReferenceLineMap::Move(const Rigid3d& new_from_old) {
  // [n; d] -> new frame: [R, [t]x R; 0, R], the SE(3) adjoint in the [v; w] ordering.
  const Matrix6d transform = Adjoint(new_from_old);
  double parameters[kLineAmbientSize];
  for (auto it = lines_.begin(); it != lines_.end();) {
    Line& line = it->second.line;
    if (!LineToParameters(TransformPluecker(new_from_old, line.line), parameters)) {
      it = lines_.erase(it);
      continue;
    }
    const Eigen::Matrix<double, 6, 4> basis = LineTangentBasis(parameters);
    const Eigen::Matrix4d move = LineTangentFromAmbient(basis) * transform * line.line_d_tangent;
    line.line = LineFromParameters(parameters);
    line.line_d_tangent = basis;
    line.tangent_covariance = move * line.tangent_covariance * move.transpose();
    Project(&it->second);
    ++it;
  }
}

const ReferenceLineMap::Line* ReferenceLineMap::Find(std::int64_t id) const {
  const auto it = lines_.find(id);
  return it == lines_.end() ? nullptr : &it->second.line;
}

bool ReferenceLineMap::FindByProjection(const Segment2d& left, const Segment2d& right, double max_px,
                                        const std::function<bool(std::int64_t)>& excluded, std::int64_t* id) {
  const Eigen::Vector3d observed[2] = {LineFromSegment(left), LineFromSegment(right)};
  const Segment2d* segments[2] = {&left, &right};
  duplicates_.clear();
  double best_distance = 0.0;
  for (const auto& [candidate, entry] : lines_) {
    if (excluded(candidate)) continue;
    const Eigen::Vector3d* projected = entry.projected;
    double largest = 0.0;
    bool near = true;
    for (int c = 0; c < 2 && near; ++c) {
      // Same orientation: a segment's line and its projection have normals of the same sign.
      near = projected[c].head<2>().dot(observed[c].head<2>()) > 0.0;
      for (int e = 0; e < 2 && near; ++e) {
        largest = std::max(largest, std::abs(SignedDistance(projected[c], segments[c]->segment<2>(2 * e))));
        near = largest <= max_px;
      }
    }
    if (!near) continue;
    if (duplicates_.empty() || largest < best_distance) {
      best_distance = largest;
      *id = candidate;
    }
    duplicates_.push_back(candidate);
  }
  for (const std::int64_t duplicate : duplicates_) {
    if (duplicate != *id) lines_.erase(duplicate);
  }
  return !duplicates_.empty();
}

}  // namespace slt
