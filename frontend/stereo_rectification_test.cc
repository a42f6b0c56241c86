#include "frontend/stereo_rectification.h"

#include <gtest/gtest.h>

#include "render/sequence_renderer.h"

namespace slt {
namespace {

// A rendered room seen through a strongly distorting lens (about EuRoC's), without noise,
// blur, vignetting or exposure changes, so that images compare pixel by pixel.
SimulationConfig DistortedRoom() {
  nlohmann::json rig = {{"width", 320},
                        {"height", 240},
                        {"left", {{"fx", 220.0}, {"fy", 220.0}, {"cx", 159.5}, {"cy", 119.5}}},
                        {"right", {{"fx", 220.0}, {"fy", 220.0}, {"cx", 159.5}, {"cy", 119.5}}},
                        {"right_from_left", {{"R", {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}, {"t", {-0.11, 0, 0}}}}};
  nlohmann::json images = {{"distortion", {-0.28, 0.07, 0.0002, 0.00002}},
                           {"read_noise", 0.0},
                           {"shot_noise", 0.0},
                           {"vignetting", 0.0},
                           {"defocus_blur_px", 0.0},
                           {"exposure_variation", 0.0}};
  return SimulationConfigFromJson({{"scene", {{"type", "room"}}}, {"frames", 2}, {"rig", rig}, {"images", images}},
                                  "test");
}

double MeanAbsoluteDifference(const cv::Mat& a, const cv::Mat& b) {
  // The outer 4 px are left out: resampling replicates the border there.
  const cv::Rect inner(4, 4, a.cols - 8, a.rows - 8);
  return cv::mean(cv::abs(cv::Mat_<float>(a(inner)) - cv::Mat_<float>(b(inner))))[0];
}

TEST(StereoRectifier, IdealRigPassesThrough) {
  DistortedStereoCalibration c;
  c.width = 64;
  c.height = 48;
  c.right_from_left = Rigid3d(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.1, 0, 0));
  const StereoRectifier rectifier(c);
  EXPECT_FALSE(rectifier.active());
  const cv::Mat image(48, 64, CV_8UC1, cv::Scalar(7));
  EXPECT_EQ(rectifier.Rectify(image, 1).data, image.data);
  c.right_from_left.translation = Eigen::Vector3d(0, -0.1, 0);
  EXPECT_THROW(StereoRectifier{c}, std::invalid_argument);
}

TEST(StereoRectifier, RectifiedRenderedImagesMatchAPinholeRenderingOfTheRectifiedRig) {
  const SimulationConfig config = DistortedRoom();
  const SimulatedSequence sequence = Simulate(config);
  const SequenceRenderer renderer(sequence, config);

  DistortedStereoCalibration calibration;
  calibration.width = sequence.true_rig.width;
  calibration.height = sequence.true_rig.height;
  calibration.left = sequence.true_rig.left;
  calibration.right = sequence.true_rig.right;
  calibration.left_distortion = calibration.right_distortion = config.images.distortion;
  calibration.right_from_left = sequence.true_rig.right_from_left;
  const StereoRectifier rectifier(calibration);
  ASSERT_TRUE(rectifier.active());
  // Both cameras already share one orientation: rectification only undistorts (and zooms).
  EXPECT_TRUE(rectifier.rectified_from_left().isIdentity(1e-9));
  EXPECT_GT(rectifier.rig().left.fx, 0.0);

  // The reference: the same scene rendered by an undistorted camera with the rectified rig.
  SimulationConfig pinhole_config = config;
  pinhole_config.images.distortion = {};
  SimulatedSequence pinhole = sequence;
  pinhole.true_rig = rectifier.rig();
  const SequenceRenderer reference(pinhole, pinhole_config);
  for (int camera = 0; camera < 2; ++camera) {
    const cv::Mat distorted = renderer.Image(1, camera);
    const cv::Mat expected = reference.Image(1, camera);
    const double rectified_error = MeanAbsoluteDifference(rectifier.Rectify(distorted, camera), expected);
    const double distorted_error = MeanAbsoluteDifference(distorted, expected);
    EXPECT_LT(rectified_error, 1.5) << "camera " << camera;
    EXPECT_GT(distorted_error, 4.0 * rectified_error) << "camera " << camera;
  }
}

}  // namespace
}  // namespace slt
