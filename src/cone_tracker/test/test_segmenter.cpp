// Segmentation on rig_sim frames rendered at known poses, against the
// projected truth (peak; the base surface point facing the camera, 3.1.4).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "cone_tracker/testing/vision_frames.h"
#include "cone_tracker/vision/segmenter.h"

namespace cone_tracker {
namespace {

// The target (1 px RMS); test_refinement.cpp measures it over many views.
constexpr double kPeakTolPx = 2.0;
constexpr double kBaseTolPx = 2.0;
constexpr double kRmsTolPx = 1.0;

// Each truth cone matched to the nearest detection; returns the RMS peak/base error.
double MatchRms(const SimFrame& f, const SegmentationResult& r, size_t expected) {
  EXPECT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.cones.size(), expected);
  if (r.cones.size() != expected)
    for (const ConeDetection& d : r.cones)
      std::printf("cone peak %.1f %.1f base %.1f %.1f area %.0f frag %d ratio %.2f sol %.2f\n", d.peak_px.x(),
                  d.peak_px.y(), d.base_px.x(), d.base_px.y(), d.blob.area, d.blob.fragments, d.blob.axis_ratio,
                  d.blob.solidity);
  if (r.cones.size() != expected)
    for (const ConeDetection& d : r.rejected)
      std::printf("rejected bbox %d %d %d %d area %.0f frag %d ratio %.2f gates 0x%x\n", d.blob.bbox_x, d.blob.bbox_y,
                  d.blob.bbox_w, d.blob.bbox_h, d.blob.area, d.blob.fragments, d.blob.axis_ratio, d.failed_gates);
  double sum = 0.0;
  int n = 0;
  for (const TruthCone& t : f.truth) {
    if (!std::isfinite(t.peak_px.x())) continue;
    double best = 1e9;
    const ConeDetection* match = nullptr;
    for (const ConeDetection& d : r.cones) {
      const double e = (d.peak_px - t.peak_px).norm() + (d.base_px - t.base_px).norm();
      if (e < best) best = e, match = &d;
    }
    if (!match) continue;
    const double ep = (match->peak_px - t.peak_px).norm(), eb = (match->base_px - t.base_px).norm();
    EXPECT_LT(ep, kPeakTolPx) << "peak " << match->peak_px.transpose() << " truth " << t.peak_px.transpose();
    EXPECT_LT(eb, kBaseTolPx) << "base " << match->base_px.transpose() << " truth " << t.base_px.transpose();
    sum += ep * ep + eb * eb, n += 2;
  }
  return n ? std::sqrt(sum / n) : INFINITY;
}

}  // namespace

TEST(Segmenter, DefaultLayoutRoadConesAtThreeMetres) {
  const rig_sim::Scene scene = rig_sim::DefaultScene();
  Segmenter seg{SegmenterConfig()};
  for (double az : {0.3, 1.4, 2.6}) {
    const Eigen::Vector3d eye(3.2 * std::cos(az), 3.2 * std::sin(az), 1.5);
    const SimFrame f = RenderSim(scene, LookAt(eye, Eigen::Vector3d(0, 0, 0.3)));
    const SegmentationResult r = seg.Process(FrameView(f), f.camera);
    const double rms = MatchRms(f, r, 3);
    std::printf("default layout, azimuth %.1f rad: peak/base RMS %.2f px\n", az, rms);
    EXPECT_LT(rms, kRmsTolPx) << "azimuth " << az;
    for (const ConeDetection& d : r.cones) EXPECT_EQ(d.blob.fragments, 3);  // two collars split each cone
    EXPECT_LT(r.roi_w * r.roi_h, f.camera.width_px * f.camera.height_px);
  }
}

TEST(Segmenter, IndoorFourInchConesAndUndistortion) {
  const rig_sim::Scene scene = rig_sim::EquilateralScene(0.30, 0.10, rig_sim::ConeStyle::kPlain);
  Segmenter seg{SegmenterConfig()};
  const SimFrame f = RenderSim(scene, LookAt(Eigen::Vector3d(0.55, 0.25, 0.35), Eigen::Vector3d(0, 0, 0.03)));
  const SegmentationResult r = seg.Process(FrameView(f), f.camera);
  const double rms = MatchRms(f, r, 3);
  std::printf("indoor 4-inch layout: peak/base RMS %.2f px\n", rms);
  EXPECT_LT(rms, kRmsTolPx);
  // Undistorted points agree with the pinhole projection of the same point.
  const CameraModel& cam = f.camera;
  for (const ConeDetection& d : r.cones) {
    const Eigen::Vector3d ray = cam.PixelRay(d.peak_px.x(), d.peak_px.y());
    const Eigen::Vector2d pinhole(f.camera.fx_px * ray.x() + f.camera.cx_px, f.camera.fy_px * ray.y() + f.camera.cy_px);
    EXPECT_LT((pinhole - d.peak_undist_px).norm(), 1e-3);
  }
}

// A barrel lens spreads the edge's pixels past the pinhole image's bounds: the orange regions of a blob on the left
// edge keep a column inside the image, where cone_tracker/observations (clipped to the image) and the association's
// clutter test (rig_model::UnexplainedOrange) still see that orange reaches the edge there.
TEST(Segmenter, OrangeRegionsOfABlobAtTheEdgeStayInTheImage) {
  CameraModel cam;
  cam.width_px = 512, cam.height_px = 384, cam.fx_px = cam.fy_px = 385.0, cam.cx_px = 255.5, cam.cy_px = 191.5;
  cam.distortion = {-0.3, 0.08, 0.0, 0.0, 0.0};
  std::vector<Eigen::Vector2d> corner = {{-0.5, 180.0}};
  ASSERT_TRUE(UndistortPixels(cam, &corner));
  ASSERT_LT(corner[0].x(), -2.0) << "the lens puts the edge's pixels outside the pinhole image";
  ConeDetection d;
  for (int y = 170; y < 190; ++y) d.blob.runs.push_back({y, 0, 1});
  const std::vector<rig_model::ImageBox> boxes = OrangeRegions({d}, cam);
  ASSERT_FALSE(boxes.empty());
  for (const rig_model::ImageBox& b : boxes) {
    EXPECT_GE(b.u_max, 0.0);
    EXPECT_LE(b.u_min, 511.0);
    EXPECT_GT(b.v_max, 160.0);
    EXPECT_LT(b.v_min, 200.0);
  }
}

TEST(Segmenter, BayerAndBgrGiveTheSameCones) {
  const rig_sim::Scene scene = rig_sim::DefaultScene();
  // A view where no cone overlaps another in the image (overlapping orange
  // silhouettes form one blob; not handled).
  const SimFrame f = RenderSim(
      scene, LookAt(Eigen::Vector3d(3.2 * std::cos(1.4), 3.2 * std::sin(1.4), 1.5), Eigen::Vector3d(0, 0, 0.3)));
  Segmenter seg{SegmenterConfig()};
  const CameraModel cam = f.camera;
  const SegmentationResult ref = seg.Process(FrameView(f), cam);
  ASSERT_EQ(ref.cones.size(), 3u);
  SimFrame bgr = f;
  for (size_t i = 0; i < bgr.rgb.size(); i += 3) std::swap(bgr.rgb[i], bgr.rgb[i + 2]);
  const SegmentationResult r_bgr = seg.Process(FrameView(bgr, "bgr8"), cam);
  ASSERT_EQ(r_bgr.cones.size(), 3u);
  EXPECT_EQ((r_bgr.cones[0].peak_px - ref.cones[0].peak_px).norm(), 0.0);
  // Mosaic to RGGB (even rows R G, odd rows G B).
  const int w = f.camera.width_px, h = f.camera.height_px;
  std::vector<uint8_t> raw(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int c = (y % 2 == 0) ? (x % 2 == 0 ? 0 : 1) : (x % 2 == 0 ? 1 : 2);
      raw[size_t(y) * w + x] = f.rgb[(size_t(y) * w + x) * 3 + c];
    }
  const SegmentationResult r_bayer = seg.Process({raw.data(), w, h, w, "bayer_rggb8"}, cam);
  ASSERT_TRUE(r_bayer.ok) << r_bayer.error;
  EXPECT_LT(MatchRms(f, r_bayer, 3), kRmsTolPx);
}

TEST(Segmenter, NoConesEmptyAndBadInputGiveClearErrors) {
  rig_sim::Scene empty;
  const SimFrame f = RenderSim(empty, LookAt(Eigen::Vector3d(3, 0, 1.5), Eigen::Vector3d(0, 0, 0)));
  Segmenter seg{SegmenterConfig()};
  const CameraModel cam = f.camera;
  SegmentationResult r = seg.Process(FrameView(f), cam);
  EXPECT_TRUE(r.ok);
  EXPECT_TRUE(r.cones.empty());
  r = seg.Process(FrameView(f, "mono8"), cam);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("mono8"), std::string::npos);
  r = seg.Process({nullptr, 0, 0, 0, "rgb8"}, cam);
  EXPECT_FALSE(r.ok);
  const uint8_t one[3] = {230, 80, 10};
  r = seg.Process({one, 1, 1, 3, "rgb8"}, cam);
  EXPECT_TRUE(r.ok);
  EXPECT_TRUE(r.cones.empty());
  r = seg.Process({one, 1, 1, 1, "rgb8"}, cam);  // step too small
  EXPECT_FALSE(r.ok);
  CameraModel nan_cam = cam;
  nan_cam.distortion[0] = NAN;
  const SimFrame g = RenderSim(rig_sim::DefaultScene(), LookAt(Eigen::Vector3d(3, 0, 1.5), Eigen::Vector3d(0, 0, 0.3)));
  r = seg.Process(FrameView(g), nan_cam);  // never throws
  EXPECT_TRUE(r.ok);
  SegmenterConfig bad;
  bad.min_axis_ratio = 0.5;
  EXPECT_THROW(Segmenter{bad}, std::invalid_argument);
}

TEST(Segmenter, DistractorsAreRejectedAndConesFound) {
  rig_sim::Scene scene = rig_sim::DefaultScene();
  rig_sim::BoxSpec box;
  box.center_m = Eigen::Vector3d(1.0, 1.6, 0.15);  // beside the layout, not occluding a cone
  scene.boxes.push_back(box);
  rig_sim::PatchSpec patch;
  patch.center_m = Eigen::Vector2d(0.9, -1.3);
  scene.patches.push_back(patch);
  rig_sim::PersonSpec person;
  person.position_m = Eigen::Vector2d(-2.5, -1.5);
  scene.people.push_back(person);
  const SimFrame f = RenderSim(scene, LookAt(Eigen::Vector3d(3.4, 0.4, 1.6), Eigen::Vector3d(0, 0, 0.3)));
  Segmenter seg{SegmenterConfig()};
  const SegmentationResult r = seg.Process(FrameView(f), f.camera);
  EXPECT_LT(MatchRms(f, r, 3), kRmsTolPx);
  EXPECT_GE(r.rejected.size(), 1u);
}

TEST(Segmenter, ConeCutByTheBorderIsRejected) {
  const SimFrame f =
      RenderSim(rig_sim::DefaultScene(),
                LookAt(Eigen::Vector3d(3.2 * std::cos(1.4), 3.2 * std::sin(1.4), 1.5), Eigen::Vector3d(0, 0, 0.3)));
  Segmenter seg{SegmenterConfig()};
  const CameraModel cam = f.camera;
  const SegmentationResult full = seg.Process(FrameView(f), cam);
  ASSERT_EQ(full.cones.size(), 3u);
  // Crop the frame so that its left edge runs through the leftmost cone's axis.
  const int x0 = int(full.cones[0].peak_px.x());
  ImageView cut = FrameView(f);
  cut.data += 3 * x0;
  cut.width -= x0;
  const SegmentationResult r = seg.Process(cut, cam);
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.cones.size(), 2u);
  bool border_rejected = false;
  for (const ConeDetection& d : r.rejected) border_rejected |= (d.failed_gates & kGateBorder) != 0;
  EXPECT_TRUE(border_rejected);
}

}  // namespace cone_tracker
