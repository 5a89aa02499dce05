// The 7.2 measurement on frames made by our own renderer: the platform's blue
// dots and the red dots drawn together, the red grid placed exactly between
// the blue one or moved by a known amount on the platform.
#include <gtest/gtest.h>

#include <cmath>

#include "ar_overlay/core/mesh_generators.h"
#include "ar_overlay/core/overlay.h"
#include "ar_overlay/core/platform_alignment.h"
#include "ar_overlay/core/scene.h"
#include "rig_model/layout.h"

namespace ar_overlay {
namespace {

const std::string kOverlayDir = AR_OVERLAY_DIR;

// A frame of the platform seen obliquely through a distorted lens, image right
// along the platform's +x; the red grid offset by (dx, dy) metres on the platform.
cv::Mat PlatformFrame(const CameraModel& k, double dx_m, double dy_m,
                      const Eigen::Vector3d& eye = Eigen::Vector3d(0.0, -0.6, 1.0)) {
  Overlay overlay;
  ModelSpec blue, red;
  blue.name = "blue";
  blue.T_parent_origin.translation() << 0, 0, 0.05;
  red.name = "red";
  red.T_parent_origin.translation() << dx_m, dy_m, 0.0501;
  overlay.AddModel(blue, DotGrid(5, 5, 0.1f, 0.02f, 32, {0, 0, 1, 1}));
  overlay.AddModel(red, DotGrid(4, 4, 0.1f, 0.015f, 32, {1, 0, 0, 1}));
  const cv::Mat grey(k.height_px, k.width_px, CV_8UC3, cv::Scalar(150, 150, 150));
  cv::Mat out;
  std::string enc;
  overlay.Process(grey, "bgr8", k, CameraLookAt(eye, {0.0, 0.0, 0.05}).inverse(), out, enc);
  return out;
}

const CameraModel kPlatformCamera{640, 480, 560, 560, 319.5, 239.5, {-0.2, 0.05, 0, 0, 0}};

TEST(PlatformAlignment, SegmentsEveryDotOfBothGrids) {
  const cv::Mat frame = PlatformFrame(kPlatformCamera, 0, 0);
  EXPECT_EQ(SegmentDots(frame, DotColour::kBlue, AlignmentConfig()).size(), 25u);
  EXPECT_EQ(SegmentDots(frame, DotColour::kRed, AlignmentConfig()).size(), 16u);
  const cv::Mat grey(100, 100, CV_8UC3, cv::Scalar(150, 150, 150));  // nothing in a grey frame
  EXPECT_TRUE(SegmentDots(grey, DotColour::kBlue, AlignmentConfig()).empty());
}

TEST(PlatformAlignment, AlignedGridsGiveNoErrorAndAnOffsetIsMeasuredInInches) {
  const AlignmentStats aligned =
      Summarize(MeasureAlignment(PlatformFrame(kPlatformCamera, 0, 0), kPlatformCamera, AlignmentConfig()));
  ASSERT_EQ(aligned.dots, 16u);
  EXPECT_LT(std::hypot(aligned.mean_px.x, aligned.mean_px.y), 0.15);
  EXPECT_LT(std::max(aligned.std_px.x, aligned.std_px.y), 0.2);
  // 1 cm along the platform's x (image right): 0.394 inch; the cell scale is local, so within 10 %.
  const AlignmentStats moved =
      Summarize(MeasureAlignment(PlatformFrame(kPlatformCamera, 0.01, 0), kPlatformCamera, AlignmentConfig()));
  ASSERT_EQ(moved.dots, 16u);
  EXPECT_NEAR(moved.mean_inch.x, 0.01 / 0.0254, 0.04);
  EXPECT_NEAR(moved.mean_inch.y, 0.0, 0.04);
  EXPECT_GT(moved.mean_px.x, 3.0);
  // Without undoing the distortion the middle is wrong at the edges: the camera matters.
  CameraModel pinhole = kPlatformCamera;
  pinhole.distortion.clear();
  const AlignmentStats raw =
      Summarize(MeasureAlignment(PlatformFrame(kPlatformCamera, 0, 0), pinhole, AlignmentConfig()));
  EXPECT_GT(std::max(raw.std_px.x, raw.std_px.y), aligned.std_px.x);
}

TEST(PlatformAlignment, GrazingViewStillFindsEachRedDotsOwnCell) {
  // Seen at about 17 degrees the cells are four times wider than tall, and the next row's dots
  // are nearer to a red dot than its own cell's far corners.
  const AlignmentStats s = Summarize(
      MeasureAlignment(PlatformFrame(kPlatformCamera, 0, 0, {0.0, -1.4, 0.48}), kPlatformCamera, AlignmentConfig()));
  EXPECT_EQ(s.dots, 16u);
  EXPECT_LT(std::hypot(s.mean_px.x, s.mean_px.y), 0.3);
  EXPECT_LT(std::max(s.std_px.x, s.std_px.y), 0.4);
}

TEST(PlatformAlignment, AGridSeenInPartGivesNoMeasurement) {
  cv::Mat frame = PlatformFrame(kPlatformCamera, 0, 0);
  // Paint over the blue dots of the left half, as a cone in front of the platform would.
  cv::Mat left = frame(cv::Rect(0, 0, 320, 480));
  left.setTo(cv::Scalar(150, 150, 150), DotMask(left, DotColour::kBlue));
  EXPECT_TRUE(MeasureAlignment(frame, kPlatformCamera, AlignmentConfig()).empty());
  EXPECT_EQ(Summarize({}).dots, 0u);
}

TEST(PlatformAlignment, SceneMatchesTheLayoutsPlatform) {
  // The red grid of scene_platform.yaml sits between the platform's blue grid (rig_model's
  // layouts/platform.yaml, which rig_sim renders).
  const rig_model::Layout layout =
      rig_model::LoadLayoutFile(kOverlayDir + "/../rig_model/config/layouts/platform.yaml");
  ASSERT_EQ(layout.platforms.size(), 1u);
  const rig_model::PlatformSpec& p = layout.platforms[0];
  EXPECT_DOUBLE_EQ(p.spacing_m, 0.1);
  EXPECT_EQ(p.rows, 5);
  EXPECT_EQ(p.cols, 5);
  const auto specs = LoadSceneYaml(kOverlayDir + "/config/scene_platform.yaml");
  ASSERT_EQ(specs.size(), 1u);
  const Eigen::Vector3d t = specs[0].T_parent_origin.translation();
  EXPECT_DOUBLE_EQ(t.x(), p.center_m.x());
  EXPECT_DOUBLE_EQ(t.y(), p.center_m.y());
  EXPECT_DOUBLE_EQ(t.z(), p.size_m.z());  // on the board's top face
}

}  // namespace
}  // namespace ar_overlay
