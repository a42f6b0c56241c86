#include "frontend/line_detection.h"

#include <gtest/gtest.h>

#include <memory>
#include <opencv2/imgproc.hpp>

namespace slt {
namespace {

double Length(const Segment2d& s) { return (s.tail<2>() - s.head<2>()).norm(); }

TEST(MergeCollinearSegments, JoinsCollinearFragmentsAcrossASmallGap) {
  const DetectionOptions options;  // 2 deg, 1.5 px, 6 px gap
  std::vector<Segment2d> segments = {Segment2d(10, 50, 60, 50), Segment2d(64, 50.5, 120, 50.5),
                                     Segment2d(10, 60, 60, 60)};  // the third is 10 px away
  MergeCollinearSegments(options, &segments);
  ASSERT_EQ(segments.size(), 2u);
  EXPECT_NEAR(Length(segments[0]), 110.0, 0.1);
  EXPECT_NEAR(Length(segments[1]), 50.0, 1e-9);
}

TEST(MergeCollinearSegments, OrientedFragmentsOfOppositeDirectionStayApart) {
  const DetectionOptions options;
  // Collinear, 4 px apart along the line, pointing opposite ways (opposite polarity).
  const std::vector<Segment2d> fragments = {Segment2d(10, 50, 60, 50), Segment2d(120, 50, 64, 50)};
  std::vector<Segment2d> undirected = fragments, oriented = fragments;
  MergeCollinearSegments(options, &undirected, false);
  MergeCollinearSegments(options, &oriented, true);
  EXPECT_EQ(undirected.size(), 1u);
  ASSERT_EQ(oriented.size(), 2u);
  // Oriented fragments pointing the same way still merge, keeping their direction; also across
  // the wrap of the angle at 0 / 360 deg (directions just above and just below 0).
  std::vector<Segment2d> same = {Segment2d(10, 50, 60, 50.5), Segment2d(64, 50.4, 120, 49.9)};
  MergeCollinearSegments(options, &same, true);
  ASSERT_EQ(same.size(), 1u);
  EXPECT_GT(same[0][2], same[0][0]);
}

// An edge whose brighter side changes half way along it (a shelf's edge under a light and a
// dark book): two segments of one polarity each. Merged across the change the two halves'
// contrasts cancel and the contrast filter drops the line.
TEST(DetectLines, EveryDetectorFindsTheSameLinesInAViewIntoALargerImage) {
  // A view (not continuous in memory) into a larger image, as the flow pyramid's level 0 is:
  // each detector finds what it finds in a copy of the same pixels.
  cv::Mat large(300, 400, CV_8UC1, cv::Scalar(60));
  cv::rectangle(large, cv::Point(80, 60), cv::Point(250, 180), cv::Scalar(180), cv::FILLED);
  cv::line(large, cv::Point(40, 230), cv::Point(330, 200), cv::Scalar(200), 5);
  cv::GaussianBlur(large, large, cv::Size(5, 5), 1.0);
  const cv::Mat view = large(cv::Rect(20, 20, 340, 260));
  ASSERT_FALSE(view.isContinuous());
  for (const auto& [type, name] : LineDetectorNames()) {
    DetectionOptions options;
    options.detector = type;
    const std::unique_ptr<LineDetector> detector = MakeLineDetector(options);
    const std::vector<ImageLine> in_view = DetectLines(*detector, options, view);
    const std::vector<ImageLine> in_copy = DetectLines(*detector, options, view.clone());
    ASSERT_EQ(in_view.size(), in_copy.size()) << name;
    EXPECT_GE(in_copy.size(), 2u) << name;
    for (size_t i = 0; i < in_view.size(); ++i) EXPECT_LT((in_view[i].segment - in_copy[i].segment).norm(), 1e-9) << name;
  }
}

TEST(DetectLines, KeepsAnEdgeWhosePolarityChangesAsTwoSegments) {
  cv::Mat image(120, 240, CV_8UC1, cv::Scalar(100));
  image(cv::Rect(20, 30, 100, 30)).setTo(160);   // above the edge at row 60, left: brighter
  image(cv::Rect(120, 30, 100, 30)).setTo(40);   // right: darker
  cv::GaussianBlur(image, image, cv::Size(0, 0), 0.8);
  DetectionOptions options;
  options.merge_gap_px = 12.0;  // so that the old merge would join the halves across their gap
  const std::unique_ptr<LineDetector> detector = MakeLineDetector(options);
  const auto on_edge = [](const std::vector<ImageLine>& lines) {
    std::vector<ImageLine> found;
    for (const ImageLine& l : lines) {
      if (std::abs(l.segment[1] - 59.5) < 1.5 && std::abs(l.segment[3] - 59.5) < 1.5) found.push_back(l);
    }
    return found;
  };
  const std::vector<ImageLine> by_polarity = on_edge(DetectLines(*detector, options, image));
  ASSERT_EQ(by_polarity.size(), 2u);
  for (const ImageLine& l : by_polarity) {
    EXPECT_GT(l.Length(), 80.0);
    EXPECT_GT(l.contrast, 40.0f);
  }
  // Oriented: brighter side at +n = (-d_v, d_u); above the edge (smaller v) is +n when the
  // segment points left (d = (-1, 0)), so the left half points left, the right half right.
  const ImageLine& left = by_polarity[0].segment[0] < by_polarity[1].segment[0] ? by_polarity[0] : by_polarity[1];
  const ImageLine& right = &left == &by_polarity[0] ? by_polarity[1] : by_polarity[0];
  EXPECT_LT(left.segment[2], left.segment[0]);
  EXPECT_GT(right.segment[2], right.segment[0]);

  options.merge_same_polarity = false;
  EXPECT_TRUE(on_edge(DetectLines(*detector, options, image)).empty());
}

// EDLines' gradient threshold decides the weakest step it sees: a 6-grey-level edge (the weak
// steps the rendered rooms' misses are made of, docs/frontend.md) is below OpenCV's default
// 20 and above 12.
TEST(EdlinesDetector, GradientThresholdSetsTheWeakestStepFound) {
  cv::Mat image(120, 240, CV_8UC1, cv::Scalar(100));
  image(cv::Rect(0, 0, 240, 60)).setTo(106);  // a horizontal edge at row 60, 6 levels
  cv::GaussianBlur(image, image, cv::Size(0, 0), 0.8);
  const auto finds_edge = [&](int threshold) {
    DetectionOptions options;
    options.detector = LineDetectorType::kEdlines;
    options.edlines_gradient_threshold = threshold;
    std::vector<Segment2d> segments;
    MakeLineDetector(options)->Detect(image, &segments);
    for (const Segment2d& s : segments) {
      if (std::abs(s[1] - 59.5) < 1.5 && std::abs(s[3] - 59.5) < 1.5 && Length(s) > 150.0) return true;
    }
    return false;
  };
  EXPECT_FALSE(finds_edge(20));
  EXPECT_TRUE(finds_edge(12));
}

TEST(LiesAlong, ComparesDirectionEitherWayRoundAndBothEndpointsDistanceToTheLine) {
  const Segment2d line(0, 0, 100, 0);
  const double cos_2deg = std::cos(2.0 * M_PI / 180.0);
  // Beyond the line's own extent and pointing the other way: along it.
  EXPECT_TRUE(LiesAlong(line, Segment2d(300, 1, 150, 1), cos_2deg, 1.5));
  // One endpoint 2 px off (within the angle): not along it at 1.5 px.
  EXPECT_FALSE(LiesAlong(line, Segment2d(150, 1, 300, 2), cos_2deg, 1.5));
  EXPECT_TRUE(LiesAlong(line, Segment2d(150, 1, 300, 2), cos_2deg, 2.5));
  // 3 deg off, endpoints within the distance: not along it.
  EXPECT_FALSE(LiesAlong(line, Segment2d(0, -1, 38, 1), cos_2deg, 1.5));
}

// LSD's parameters come from the options (a config's detection.lsd_*, validated by key).
TEST(MakeLineDetector, LsdTakesItsParametersFromTheOptions) {
  // A bar 3 px wide, brighter than its surroundings: two edges of opposite polarity.
  cv::Mat image(120, 240, CV_8UC1, cv::Scalar(90));
  image(cv::Rect(20, 58, 200, 3)).setTo(150);
  cv::GaussianBlur(image, image, cv::Size(0, 0), 0.5);
  const auto long_segments = [&](const DetectionOptions& options) {
    std::vector<Segment2d> segments;
    MakeLineDetector(options)->Detect(image, &segments);
    int n = 0;
    for (const Segment2d& s : segments) n += (s.tail<2>() - s.head<2>()).norm() > 100.0;
    return n;
  };
  DetectionOptions options;
  options.detector = LineDetectorType::kLsd;  // LSD's parameters, whatever the default detector
  options.lsd_sigma_scale = 0.4;
  EXPECT_EQ(long_segments(options), 2);
  options.lsd_sigma_scale = 3.0;  // a blur of 5 px merges the bar's edges
  EXPECT_NE(long_segments(options), 2);
  try {
    FrontEndOptionsFromJson({{"detection", {{"lsd_density", 2.0}}}}, "f.json");
    ADD_FAILURE() << "lsd_density 2 accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("detection.lsd_density"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace slt
