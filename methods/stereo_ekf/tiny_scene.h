// For the feature models' tests (not linked into the trackers): a few 3-D segments in front of
// a rig, projected into a stereo frame with ids 10, 13, 16, 19 and the endpoints in the same
// order in both images (as the simulator writes them); a small motion; a pose near another; a
// feature model evaluated on a pair of frames.
#pragma once

#include <cstdint>
#include <ostream>
#include <tuple>
#include <utility>
#include <vector>

#include "dataset/stereo_sequence.h"
#include "geometry/se3.h"
#include "methods/stereo_ekf/feature_model.h"

namespace slt {

struct TinyScene {
  StereoRig rig;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> lines = {
      {{-0.10, 0.05, 0.50}, {0.12, -0.06, 0.62}},
      {{0.05, -0.12, 0.45}, {0.02, 0.14, 0.55}},
      {{-0.15, -0.10, 0.70}, {-0.05, 0.10, 0.40}},
      {{0.10, 0.10, 0.60}, {0.16, -0.12, 0.52}},
  };

  StereoFrame Frame(const Rigid3d& cam_from_ref) const {
    StereoFrame f;
    const Rigid3d right_from_ref = rig.right_from_left * cam_from_ref;
    for (size_t i = 0; i < lines.size(); ++i) {
      const auto& [p, q] = lines[i];
      Segment2d l, r;
      l << rig.left.Project(cam_from_ref * p), rig.left.Project(cam_from_ref * q);
      r << rig.right.Project(right_from_ref * p), rig.right.Project(right_from_ref * q);
      f.left.push_back({static_cast<std::int64_t>(10 + 3 * i), l});
      f.right.push_back({static_cast<std::int64_t>(10 + 3 * i), r});
    }
    return f;
  }
};

inline Rigid3d SomeMotion() {
  Vector6d xi;
  xi << 0.02, -0.01, 0.015, 0.01, -0.02, 0.015;
  return ExpSE3(xi);
}

// A pose near `truth` where a feature's residual and Jacobian are checked away from the truth.
inline Rigid3d NearTruth(const Rigid3d& truth) {
  return ExpSE3((Vector6d() << 0.002, 0.001, -0.003, 0.004, -0.002, 0.003).finished()) * truth;
}

// Feature `index` of a new Model (a FeatureModel) on the reference and current frames, at
// `cam_from_ref`: what the numeric derivatives over the observations evaluate once per step.
// False when the model has no block there.
template <typename Model, typename Options>
bool EvaluateOnFrames(const Options& options, const StereoRig& rig, const StereoFrame& reference,
                      const StereoFrame& current, int index, const Rigid3d& cam_from_ref, bool with_covariance,
                      FeatureBlock* block) {
  Model model(options);
  model.Reset(rig);
  model.SetReference(reference);
  model.SetCurrent(current);
  return model.Evaluate(index, cam_from_ref, with_covariance, block);
}

// What a model makes of a reference and a current frame: the counts SetReference, SetCurrent
// and CurrentStereoFeatures return and the ids of its features in order (FeatureId).
struct Association {
  int reference = 0, current = 0, current_stereo = 0;
  std::vector<std::int64_t> ids;
  bool operator==(const Association& o) const {
    return std::tie(reference, current, current_stereo, ids) == std::tie(o.reference, o.current, o.current_stereo, o.ids);
  }
};
inline std::ostream& operator<<(std::ostream& out, const Association& a) {
  out << "reference " << a.reference << ", current " << a.current << ", current stereo " << a.current_stereo << ", ids";
  for (std::int64_t id : a.ids) out << " " << id;
  return out;
}
template <typename Model>
Association Associate(Model& model, const StereoRig& rig, const StereoFrame& reference, const StereoFrame& current) {
  Association a;
  model.Reset(rig);
  a.reference = model.SetReference(reference);
  a.current = model.SetCurrent(current);
  a.current_stereo = model.CurrentStereoFeatures();
  for (int i = 0; i < model.NumFeatures(); ++i) a.ids.push_back(model.FeatureId(i));
  return a;
}

}  // namespace slt
