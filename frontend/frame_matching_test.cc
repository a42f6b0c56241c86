#include "frontend/frame_matching.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "frontend/line_detection.h"
#include "frontend/rendered_pair.h"

namespace slt {
namespace {

struct Described {
  std::vector<Segment2d> segments;
  std::vector<MsldDescriptor> descriptors;
};

Described DetectAndDescribe(const cv::Mat& image) {
  const DetectionOptions options;
  std::unique_ptr<LineDetector> detector = MakeLineDetector(options);
  MsldExtractor msld;
  msld.SetImage(image);
  Described out;
  for (const ImageLine& line : DetectLines(*detector, options, image)) {
    MsldDescriptor d;
    if (!msld.Compute(line.segment, &d)) continue;
    out.segments.push_back(line.segment);
    out.descriptors.push_back(d);
  }
  return out;
}

TEST(MatchAcrossFrames, FindsLinesAfterAKnownShiftNearTheirPrediction) {
  // A rendered room image and the same image shifted by 37 px right and 14 px up (beyond any
  // LK window); the prediction is off by (4, -3) px.
  const RenderedRoom room;
  const cv::Mat a = room.Image(0, 0);
  const Eigen::Vector2d shift(37.0, -14.0), prediction_error(4.0, -3.0);
  cv::Mat b;
  const cv::Mat translation = (cv::Mat_<double>(2, 3) << 1, 0, shift.x(), 0, 1, shift.y());
  cv::warpAffine(a, b, translation, a.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  const Described before = DetectAndDescribe(a), after = DetectAndDescribe(b);
  std::vector<FrameMatchQuery> queries;
  const Eigen::Vector4d predicted_shift = (Eigen::Vector4d() << shift + prediction_error, shift + prediction_error).finished();
  for (size_t i = 0; i < before.segments.size(); ++i) {
    const Segment2d moved = before.segments[i] + predicted_shift;
    // Lines that stay well inside the shifted image.
    if (moved.minCoeff() < 30.0 || std::max(moved[0], moved[2]) > a.cols - 30.0 || std::max(moved[1], moved[3]) > a.rows - 30.0) continue;
    queries.push_back({moved, before.descriptors[i], 10.0});
  }
  ASSERT_GE(queries.size(), 40u);
  std::vector<FrameMatch> matches;
  MatchAcrossFrames(FrameMatchGates(), queries, after.segments, after.descriptors, &matches);
  int correct = 0;
  for (const FrameMatch& m : matches) {
    // Correct: the candidate lies on the query's line moved by the true shift.
    const Segment2d truth = queries[m.query].predicted - (Eigen::Vector4d() << prediction_error, prediction_error).finished();
    correct += InsidePredictionGate(truth, after.segments[m.candidate], 2.0, 1.5);
  }
  EXPECT_GE(matches.size(), 0.7 * queries.size()) << matches.size() << " of " << queries.size();
  EXPECT_GE(correct, 0.97 * matches.size()) << correct << " of " << matches.size();
  // One-to-one.
  std::vector<int> used;
  for (const FrameMatch& m : matches) used.push_back(m.candidate);
  std::sort(used.begin(), used.end());
  EXPECT_EQ(std::adjacent_find(used.begin(), used.end()), used.end());

  // Without the prediction (queries where the lines were), the gate finds (almost) none.
  for (FrameMatchQuery& q : queries) q.predicted -= predicted_shift;
  MatchAcrossFrames(FrameMatchGates(), queries, after.segments, after.descriptors, &matches);
  EXPECT_LT(matches.size(), 0.2 * queries.size());
}

TEST(InsidePredictionGate, AngleDistanceAndOverlap) {
  const Segment2d p(100, 100, 200, 100);
  EXPECT_TRUE(InsidePredictionGate(p, Segment2d(120, 105, 250, 104), 5.0, 10.0));
  EXPECT_FALSE(InsidePredictionGate(p, Segment2d(120, 115, 250, 114), 5.0, 10.0));   // too far
  EXPECT_FALSE(InsidePredictionGate(p, Segment2d(250, 104, 120, 105), 5.0, 10.0));   // reversed
  EXPECT_FALSE(InsidePredictionGate(p, Segment2d(120, 100, 220, 130), 5.0, 40.0));   // 17 deg off
  EXPECT_FALSE(InsidePredictionGate(p, Segment2d(210, 101, 300, 101), 5.0, 10.0));   // no overlap
}

}  // namespace
}  // namespace slt
