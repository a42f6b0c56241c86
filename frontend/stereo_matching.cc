#include "frontend/stereo_matching.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>

#include "frontend/image_sampling.h"
#include "frontend/line_motion.h"
#include "geometry/se3.h"

namespace slt {
namespace {

Eigen::Vector3d H(const Eigen::Vector2d& p) { return {p.x(), p.y(), 1.0}; }

// |sine| of the angle between a segment and the epipolar line through its midpoint (the line
// through the image's epipole).
double SineToEpipolarLine(const Segment2d& segment, const Eigen::Vector3d& epipole) {
  const Eigen::Vector2d a = segment.head<2>(), b = segment.tail<2>();
  const Eigen::Vector3d epipolar = epipole.cross(H(0.5 * (a + b)));
  const Eigen::Vector2d dir = (b - a).normalized();
  const double norm = epipolar.head<2>().norm();
  if (norm == 0.0) return 1.0;
  // The line's normal is (a, b): the sine of the angle between the segment and the line is
  // the cosine between the segment and the normal.
  return std::abs(dir.dot(epipolar.head<2>()) / norm);
}

// Both right endpoints within `distance_px` of the epipolar line of the left midpoint.
bool OnEpipolarLineOfMidpoint(const Eigen::Matrix3d& f, const Segment2d& left, const Segment2d& right,
                              double distance_px) {
  const Eigen::Vector3d l = f * H(0.5 * (left.head<2>() + left.tail<2>()));
  const double n = l.head<2>().norm();
  if (n == 0.0) return false;
  return std::abs(l.dot(H(right.head<2>()))) / n <= distance_px && std::abs(l.dot(H(right.tail<2>()))) / n <= distance_px;
}

// Across the beam: s(p) = signed distance of a right point from the epipolar line of the left
// segment's first endpoint x (the row difference in a rectified rig). The left segment spans
// [0, w] in s (w: from the epipolar line of x to that of y, which nearly coincide), the right
// one [s(x'), s(y')]; the shorter extent must lie within the longer one widened by
// `distance_px` (one end hidden in one image shortens that extent). A 3-D line whose left image
// is near an epipolar line lies near an epipolar plane, so its right image is near one too: a
// right segment steeper than twice the left's bound is another line.
bool SameExtentAcrossBeam(const Eigen::Matrix3d& f, const Eigen::Vector3d& right_epipole, const Segment2d& left,
                          const Segment2d& right, double epipolar_sine, double distance_px) {
  if (SineToEpipolarLine(right, right_epipole) >= 2.0 * epipolar_sine) return false;
  const Eigen::Vector3d lx = f * H(left.head<2>());
  Eigen::Vector3d ly = f * H(left.tail<2>());
  // A segment across the left epipole (converging cameras) gets opposite orientations.
  if (lx.head<2>().dot(ly.head<2>()) < 0.0) ly = -ly;
  const double nx = lx.head<2>().norm(), ny = ly.head<2>().norm();
  if (nx == 0.0 || ny == 0.0) return false;
  const Eigen::Vector3d a = H(right.head<2>()), b = H(right.tail<2>());
  const double sa = lx.dot(a) / nx, sb = lx.dot(b) / nx;
  const double w = 0.5 * (sa - ly.dot(a) / ny + sb - ly.dot(b) / ny);
  const double l0 = std::min(0.0, w), l1 = std::max(0.0, w), r0 = std::min(sa, sb), r1 = std::max(sa, sb);
  const double d = distance_px;
  return l1 - l0 <= r1 - r0 ? (l0 >= r0 - d && l1 <= r1 + d) : (r0 >= l0 - d && r1 <= l1 + d);
}

}  // namespace

StereoGeometry::StereoGeometry(const StereoRig& rig) {
  const Eigen::Matrix3d& r = rig.right_from_left.rotation;
  const Eigen::Vector3d& t = rig.right_from_left.translation;
  Eigen::Matrix3d tx;
  tx << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
  f_ = rig.right.K().inverse().transpose() * tx * r * rig.left.K().inverse();
  f_ /= f_.norm();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(f_, Eigen::ComputeFullU | Eigen::ComputeFullV);
  left_epipole_ = svd.matrixV().col(2);
  right_epipole_ = svd.matrixU().col(2);
  const double b = t.norm();
  rectified_ = (r - Eigen::Matrix3d::Identity()).norm() < 1e-9 && std::abs(t.y()) < 1e-9 * b &&
               std::abs(t.z()) < 1e-9 * b && t.x() < 0 && std::abs(rig.left.fy - rig.right.fy) < 1e-9 * rig.left.fy &&
               std::abs(rig.left.cy - rig.right.cy) < 1e-9;
}

double StereoGeometry::EpipolarSine(const Segment2d& left) const { return SineToEpipolarLine(left, left_epipole_); }

double StereoGeometry::BeamOverlap(const Segment2d& left, const Segment2d& right, double epipolar_sine,
                                   double epipolar_distance_px, OverlapOf of, AlongEpipolar along) const {
  if (EpipolarSine(left) < epipolar_sine) {
    const bool agree = along == AlongEpipolar::kOnMidpointLine
                           ? OnEpipolarLineOfMidpoint(f_, left, right, epipolar_distance_px)
                           : SameExtentAcrossBeam(f_, right_epipole_, left, right, epipolar_sine, epipolar_distance_px);
    return agree ? 1.0 : 0.0;
  }
  const Eigen::Vector2d x = left.head<2>(), y = left.tail<2>();
  const double length = (y - x).norm();
  const Eigen::Vector3d line = H(x).cross(H(y));
  const Eigen::Vector2d d = (y - x) / length;
  double t[2];
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector3d q = line.cross(f_.transpose() * H(k == 0 ? right.head<2>() : right.tail<2>()));
    if (std::abs(q.z()) < 1e-12) return 0.0;
    t[k] = d.dot(q.head<2>() / q.z() - x);
  }
  const double lo = std::min(t[0], t[1]), hi = std::max(t[0], t[1]);
  const double overlap = std::min(hi, length) - std::max(lo, 0.0);
  const double base = of == OverlapOf::kShorter ? std::min(length, hi - lo) : std::max(hi, length) - std::min(lo, 0.0);
  if (overlap <= 0.0 || base <= 0.0) return 0.0;
  return std::min(1.0, overlap / base);
}

bool StereoGeometry::DisparityInRange(const Segment2d& left, const Segment2d& right, double min_px,
                                      double max_px) const {
  if (!rectified_) return true;
  const double lv0 = std::min(left[1], left[3]), lv1 = std::max(left[1], left[3]);
  const double rv0 = std::min(right[1], right[3]), rv1 = std::max(right[1], right[3]);
  const double v0 = std::max(lv0, rv0), v1 = std::min(lv1, rv1);
  if (v1 - v0 >= 1.0) {
    // The disparity along a pair of image lines is linear in the row: in range over the common
    // rows when it is at both of their ends.
    const auto disparity_at = [&](double v) {
      const auto u_at = [v](const Segment2d& s) { return s[0] + (s[2] - s[0]) * (v - s[1]) / (s[3] - s[1]); };
      return u_at(left) - u_at(right);
    };
    const double d0 = disparity_at(v0), d1 = disparity_at(v1);
    return std::min(d0, d1) >= min_px && std::max(d0, d1) <= max_px;
  }
  // Along the rows: some disparity in range must make the u ranges overlap.
  const double lu0 = std::min(left[0], left[2]), lu1 = std::max(left[0], left[2]);
  const double ru0 = std::min(right[0], right[2]), ru1 = std::max(right[0], right[2]);
  return ru1 + max_px >= lu0 && ru0 + min_px <= lu1;
}

bool StereoGeometry::Transfer(const Eigen::Vector2d& left_point, const Segment2d& right,
                              Eigen::Vector2d* right_point) const {
  const Eigen::Vector3d epipolar = f_ * H(left_point);
  const Eigen::Vector3d line = H(right.head<2>()).cross(H(right.tail<2>()));
  const Eigen::Vector3d q = epipolar.cross(line);
  const double scale = epipolar.head<2>().norm() * line.head<2>().norm();
  if (std::abs(q.z()) < 1e-3 * scale) return false;  // nearly parallel
  *right_point = q.head<2>() / q.z();
  return true;
}

double SegmentCrossCorrelation(const StereoGeometry& geometry, const cv::Mat& left_grey, const cv::Mat& right_grey,
                               const Segment2d& left, const Segment2d& right, bool along_epipolar, int half_width) {
  const Eigen::Vector2d la = left.head<2>(), lb = left.tail<2>(), ra = right.head<2>(), rb = right.tail<2>();
  const double l_length = (lb - la).norm(), r_length = (rb - ra).norm();
  if (l_length < 1e-9 || r_length < 1e-9) return -1.0;
  const Eigen::Vector2d ld = (lb - la) / l_length, rd = (rb - ra) / r_length;
  const Eigen::Vector2d ln(-ld.y(), ld.x()), rn(-rd.y(), rd.x());
  constexpr int kMaxSamples = 32;
  const int samples = std::clamp(static_cast<int>(l_length / 2.0), 4, kMaxSamples);
  double sl = 0, sr = 0, sll = 0, srr = 0, slr = 0;
  int count = 0;
  for (int i = 0; i < samples; ++i) {
    const double f = (i + 0.5) / samples;
    const Eigen::Vector2d p = la + f * l_length * ld;
    Eigen::Vector2d q;
    if (along_epipolar) {
      q = ra + f * r_length * rd;
    } else {
      if (!geometry.Transfer(p, right, &q)) continue;
      const double t = rd.dot(q - ra);
      if (t < 0.0 || t > r_length) continue;  // outside the overlap
    }
    for (int o = -half_width; o <= half_width; ++o) {
      const Eigen::Vector2d pl = p + o * ln, pr = q + o * rn;
      const double a = SampleBilinear<uchar>(left_grey, pl.x(), pl.y());
      const double b = SampleBilinear<uchar>(right_grey, pr.x(), pr.y());
      sl += a;
      sr += b;
      sll += a * a;
      srr += b * b;
      slr += a * b;
      ++count;
    }
  }
  if (count < 3 * (2 * half_width + 1)) return -1.0;
  const double ml = sl / count, mr = sr / count;
  const double vl = sll / count - ml * ml, vr = srr / count - mr * mr;
  if (vl <= 1e-9 || vr <= 1e-9) return -1.0;
  return (slr / count - ml * mr) / std::sqrt(vl * vr);
}

bool SeenInPreviousPair(const StereoRig& rig, const Rigid3d& previous_from_current, const Segment2d& left,
                        const Segment2d& right, const cv::Mat (&previous_derivatives)[2], const TrackingOptions& snap,
                        double max_distance_px, SnapWorkspace* workspace) {
  StereoLineMaps maps;
  if (!PredictStereoLineMotion(rig, previous_from_current, left, right, kMinStereoPlaneSine, &maps)) return false;
  // Where the line is, not how well its direction is determined (the tracker's test).
  TrackingOptions search = snap;
  search.snap_radius_px = max_distance_px;
  for (int c = 0; c < 2; ++c) {
    Segment2d mapped;
    if (!MapSegment(c == 0 ? maps.left : maps.right, c == 0 ? left : right, &mapped)) return false;
    Segment2d snapped = mapped;
    if (!SnapSegmentToEdges(search, previous_derivatives[c], &snapped, workspace)) return false;
    const Eigen::Vector2d a = snapped.head<2>(), d = (snapped.tail<2>() - a).normalized();
    const Eigen::Vector2d n(-d.y(), d.x());
    if (std::abs(n.dot(mapped.head<2>() - a)) > max_distance_px || std::abs(n.dot(mapped.tail<2>() - a)) > max_distance_px) {
      return false;
    }
  }
  return true;
}

StereoMatcher::StereoMatcher(const MatchingOptions& options, const StereoRig& rig)
    : options_(options), geometry_(rig), epipolar_sine_(std::sin(options.epipolar_angle_deg * M_PI / 180.0)) {}

void StereoMatcher::Match(const cv::Mat& left_grey, const cv::Mat& right_grey, const std::vector<ImageLine>& left,
                          const std::vector<MsldDescriptor>& left_descriptors, const std::vector<ImageLine>& right,
                          const std::vector<MsldDescriptor>& right_descriptors, std::vector<StereoMatch>* matches,
                          const PairCheck* verify) {
  matches->clear();
  const int nl = static_cast<int>(left.size()), nr = static_cast<int>(right.size());
  candidates_.clear();
  for (int i = 0; i < nl; ++i) {
    const Segment2d& ls = left[i].segment;
    const Eigen::Vector2d ld = ls.tail<2>() - ls.head<2>();
    const double lv0 = std::min(ls[1], ls[3]) - options_.epipolar_distance_px;
    const double lv1 = std::max(ls[1], ls[3]) + options_.epipolar_distance_px;
    for (int j = 0; j < nr; ++j) {
      const Segment2d& rs = right[j].segment;
      // Cheap rejections first: rows (rectified), orientation, disparity.
      if (geometry_.rectified() && (std::max(rs[1], rs[3]) < lv0 || std::min(rs[1], rs[3]) > lv1)) continue;
      if (ld.dot(rs.tail<2>() - rs.head<2>()) <= 0.0) continue;
      if (!geometry_.DisparityInRange(ls, rs, options_.min_disparity_px, options_.max_disparity_px)) continue;
      if (geometry_.BeamOverlap(ls, rs, epipolar_sine_, options_.epipolar_distance_px) < options_.min_overlap) continue;
      candidates_.push_back({i, j, (left_descriptors[i] - right_descriptors[j]).norm(), 0.0f});
    }
  }
  // The verifications of a pair: the union overlap (of a pair that `verify` does not check) and
  // the cross-correlation.
  const bool union_test = options_.min_union_overlap > 0.0 && verify == nullptr;
  const auto accepted = [&](int i, int j, float* ncc) {
    if (union_test &&
        geometry_.BeamOverlap(left[i].segment, right[j].segment, epipolar_sine_, options_.epipolar_distance_px,
                              StereoGeometry::OverlapOf::kUnion) < options_.min_union_overlap) {
      return false;
    }
    const bool along = geometry_.EpipolarSine(left[i].segment) < epipolar_sine_;
    *ncc = static_cast<float>(SegmentCrossCorrelation(geometry_, left_grey, right_grey, left[i].segment,
                                                      right[j].segment, along, options_.ncc_half_width_px));
    return *ncc > options_.min_ncc;
  };
  const float max_distance = static_cast<float>(options_.max_msld_distance);
  const float ratio = static_cast<float>(options_.msld_ratio);
  if (verify != nullptr) {
    // Every candidate that could be a best or a second best is verified first, so that the
    // uniqueness tests below weigh only the candidates that pass.
    const float reach = ratio < 1.0f ? max_distance / ratio : max_distance;
    size_t kept = 0;
    for (Candidate& c : candidates_) {
      if (c.distance > reach || !accepted(c.left, c.right, &c.ncc) || !(*verify)(c.left, c.right)) continue;
      candidates_[kept++] = c;
    }
    candidates_.resize(kept);
  }
  // Mutual nearest neighbours with the ratio test, both ways.
  constexpr float kInf = std::numeric_limits<float>::infinity();
  best_left_.assign(nl, kInf);
  second_left_.assign(nl, kInf);
  best_left_index_.assign(nl, -1);
  best_right_.assign(nr, kInf);
  second_right_.assign(nr, kInf);
  best_right_index_.assign(nr, -1);
  best_left_candidate_.assign(nl, -1);
  for (int k = 0; k < static_cast<int>(candidates_.size()); ++k) {
    const Candidate& c = candidates_[k];
    if (c.distance < best_left_[c.left]) {
      second_left_[c.left] = best_left_[c.left];
      best_left_[c.left] = c.distance;
      best_left_index_[c.left] = c.right;
      best_left_candidate_[c.left] = k;
    } else if (c.distance < second_left_[c.left]) {
      second_left_[c.left] = c.distance;
    }
    if (c.distance < best_right_[c.right]) {
      second_right_[c.right] = best_right_[c.right];
      best_right_[c.right] = c.distance;
      best_right_index_[c.right] = c.left;
    } else if (c.distance < second_right_[c.right]) {
      second_right_[c.right] = c.distance;
    }
  }
  for (int i = 0; i < nl; ++i) {
    const int j = best_left_index_[i];
    if (j < 0 || best_right_index_[j] != i || best_left_[i] > max_distance) continue;  // mutual best
    if (ratio < 1.0f && (best_left_[i] > ratio * second_left_[i] || best_right_[j] > ratio * second_right_[j])) {
      continue;
    }
    // Without a verification: the chosen pair's checks, after the uniqueness tests (which weigh
    // every candidate of the beam).
    float ncc = candidates_[best_left_candidate_[i]].ncc;
    if (verify == nullptr && !accepted(i, j, &ncc)) continue;
    matches->push_back({i, j, best_left_[i], ncc});
  }
}

}  // namespace slt
