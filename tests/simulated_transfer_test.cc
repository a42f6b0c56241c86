// The noise-free round trip through the whole geometry: simulate a sequence, then for every
// frame and line the trifocal transfers at the true pose give back the observed lines exactly.
#include <gtest/gtest.h>

#include "geometry/line2d.h"
#include "geometry/plucker.h"
#include "geometry/trifocal.h"
#include "simulator/simulator.h"

namespace slt {
namespace {

double MaxEndpointDistance(const Eigen::Vector3d& normalized_line, const PinholeCamera& camera, const Segment2d& s) {
  const Eigen::Vector3d pixel = PixelLineFromNormalizedLine(camera, normalized_line);
  return std::max(std::abs(SignedDistance(pixel, s.head<2>())), std::abs(SignedDistance(pixel, s.tail<2>())));
}

const LineObservation* Find(const std::vector<LineObservation>& v, std::int64_t id) {
  for (const LineObservation& o : v)
    if (o.id == id) return &o;
  return nullptr;
}

TEST(SimulatedTransfer, NoiseFreeRoundTripIsExact) {
  for (const char* scene : {"paper", "room"}) {
    SimulationConfig config = SimulationConfigFromJson(
        {{"scene", {{"type", scene}}}, {"noise", {{"endpoint_px", 0.0}}}, {"frames", 40}}, "test");
    const SimulatedSequence sim = Simulate(config);
    const StereoRig& rig = sim.sequence.rig;
    const StereoFrame& ref = sim.sequence.frames[0];
    auto normalized = [&](const PinholeCamera& cam, const Segment2d& s) {
      return NormalizedLineFromPixelLine(cam, LineFromSegment(s));
    };
    double worst = 0.0;
    int checked = 0;
    for (size_t f = 1; f < sim.sequence.frames.size(); ++f) {
      const Rigid3d cam_from_ref = sim.ground_truth[f].world_from_cam.Inverse();
      const StereoFrame& cur = sim.sequence.frames[f];
      for (const LineObservation& rl : ref.left) {
        const LineObservation* rr = Find(ref.right, rl.id);
        const LineObservation* cl = Find(cur.left, rl.id);
        const LineObservation* cr = Find(cur.right, rl.id);
        if (!rr || !cl || !cr) continue;
        const Eigen::Vector3d l1 = normalized(rig.left, rl.segment), l1p = normalized(rig.right, rr->segment);
        const Eigen::Vector3d lt = normalized(rig.left, cl->segment), ltp = normalized(rig.right, cr->segment);
        double sine;
        const PlueckerLine line = StereoPairLine(rig.right_from_left, l1, l1p, nullptr, nullptr, &sine);
        if (sine < 1e-3) continue;  // in the epipolar plane: the pair does not define the line
        CurrentToReferenceTransfer c2r;
        TransferCurrentToReference(rig.right_from_left, cam_from_ref, l1p, lt, ltp, false, &c2r);
        StereoLineImages images;
        ImageLineInStereoPair(rig.right_from_left, cam_from_ref, line, false, &images);
        worst = std::max({worst, MaxEndpointDistance(c2r.via_T, rig.left, rl.segment),
                          MaxEndpointDistance(c2r.via_Tprime, rig.left, rl.segment),
                          MaxEndpointDistance(images.left, rig.left, cl->segment),
                          MaxEndpointDistance(images.right, rig.right, cr->segment)});
        ++checked;
      }
    }
    EXPECT_GT(checked, 500) << scene;
    EXPECT_LT(worst, 1e-9) << scene << ": worst endpoint distance in px";
  }
}

}  // namespace
}  // namespace slt
