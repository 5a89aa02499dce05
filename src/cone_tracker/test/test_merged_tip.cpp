// A near cone's tip in front of a farther cone (merged_tip.h). rig_sim frames at 512x384, the resolution of the
// look_away run where it was found, from behind one cone of the default layout on the line through it and a second
// cone, from_edge sideways, at heights that put the near cone's tip on or beside the far cone's base.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "cone_tracker/testing/vision_frames.h"
#include "cone_tracker/vision/merged_tip.h"
#include "cone_tracker/vision/segmenter.h"

namespace cone_tracker {
namespace {

// The accepted detection whose peak and base are both within tol_px of the truth cone's.
const ConeDetection* Found(const std::vector<ConeDetection>& cones, const TruthCone& t, double tol_px) {
  for (const ConeDetection& d : cones)
    if ((d.peak_px - t.peak_px).norm() < tol_px && (d.base_px - t.base_px).norm() < tol_px) return &d;
  return nullptr;
}

// How far an accepted detection is from the nearest truth cone (the larger of its peak's and base's errors).
double Off(const ConeDetection& d, const SimFrame& f) {
  double best = INFINITY;
  for (const TruthCone& t : f.truth)
    if (std::isfinite(t.peak_px.x()))
      best = std::min(best, std::max((d.peak_px - t.peak_px).norm(), (d.base_px - t.base_px).norm()));
  return best;
}

TEST(MergedTip, NearConesTipInFrontOfAFarConeGoesBackToIt) {
  const rig_sim::Scene scene = rig_sim::DefaultScene();
  const Eigen::Vector3d a = scene.cones[0].base_m, b = scene.cones[1].base_m;  // near, far
  const Eigen::Vector3d along = (a - b).normalized(), across(-along.y(), along.x(), 0.0);
  const double height_m = scene.cones[0].height_m, apart_m = (a - b).norm();
  const CameraModel camera = rig_model::ThesisCamera().Scaled(0.5);
  SegmenterConfig off_config;
  off_config.split_merged_tips = false;
  Segmenter on{SegmenterConfig()}, off{off_config};
  int merged = 0, gained = 0;
  for (double near_m : {1.2, 1.6})
    for (double dz_m : {-0.1, 0.0})
      for (double offset_m : {0.04, 0.08, 0.12, 0.16}) {
        // The eye's height that puts the near tip on the far base when offset_m is 0, plus dz_m.
        const double eye_z = height_m * (near_m + apart_m) / apart_m + dz_m;
        const Eigen::Vector3d eye = a + near_m * along + offset_m * across + Eigen::Vector3d(0, 0, eye_z);
        const SimFrame f = RenderSim(scene, LookAt(eye, 0.5 * (a + b) + Eigen::Vector3d(0, 0, 0.3)), camera);
        const SegmentationResult r_on = on.Process(FrameView(f), f.camera), r_off = off.Process(FrameView(f), f.camera);
        ASSERT_TRUE(r_on.ok && r_off.ok);
        const bool near_off = Found(r_off.cones, f.truth[0], 1.5) != nullptr;
        const bool near_on = Found(r_on.cones, f.truth[0], 1.5) != nullptr;
        const bool far_on = Found(r_on.cones, f.truth[1], 1.5) != nullptr;
        // Without the split the near cone is refused here: its tip is in the far cone's blob.
        merged += !near_off;
        gained += near_on && !near_off;
        EXPECT_FALSE(near_off && !near_on) << "the split lost a near cone found without it";
        EXPECT_GE(r_on.cones.size(), r_off.cones.size());
        for (const ConeDetection& d : r_on.cones) {
          bool also_off = false;  // accepted without the split too, with the same points
          for (const ConeDetection& o : r_off.cones)
            also_off = also_off || ((o.peak_px - d.peak_px).norm() < 1e-9 && (o.base_px - d.base_px).norm() < 1e-9);
          if (!also_off) {
            EXPECT_LT(Off(d, f), 1.5) << "near " << near_m << " dz " << dz_m << " offset " << offset_m;
          }
        }
        std::printf("near %.1f m, eye %.2f m high, offset %.2f m: accepted %zu -> %zu, near cone %d -> %d, far %d\n",
                    near_m, eye_z, offset_m, r_off.cones.size(), r_on.cones.size(), int(near_off), int(near_on),
                    int(far_on));
      }
  std::printf("near cone refused without the split in %d views, found with it in %d\n", merged, gained);
  EXPECT_GE(merged, 4);  // the views do merge the near tip into the far cone
  EXPECT_GE(gained, 2);
}

// The pixels of another blob inside a cone's edges above its top: a tip standing on one edge against the background.
TEST(MergedTip, FindTipInKeepsThePixelsBetweenTheEdges) {
  // A cone with its apex at (50, 0) and its edges x = 50 -+ 0.25 y, through (40, 40) and (60, 40).
  OutlineFit fit;
  fit.apex_undist_px = Eigen::Vector2d(50, 0);
  fit.left_line = Eigen::Vector3d(40, 10, -2000);   // 40 x + 10 y - 2000 = 0 through (50, 0), (40, 40); + inside
  fit.right_line = Eigen::Vector3d(-40, 10, 2000);  // through (50, 0), (60, 40); + inside
  // The other blob: rows 2..20, from the left edge's pixel to x = 80 (a far cone's body to the right).
  std::vector<cone_tracker::Run> other;
  for (int y = 2; y <= 20; ++y) other.push_back({y, int(std::ceil(50.0 - 0.25 * y)), 80});
  CameraModel pinhole;  // no lens: raw = undistorted
  // The wedge from the apex 20 px down the axis, in a 100-px-wide image.
  const auto find = [&](const std::vector<cone_tracker::Run>& runs, const OutlineFit& f) {
    TipWedge wedge;
    EXPECT_TRUE(MakeTipWedge(f, Eigen::Vector2d(0, 1), 20.0, pinhole, &wedge));
    return FindTipIn(runs, wedge, pinhole, 1.0, 100);
  };
  const TipPiece p = find(other, fit);
  ASSERT_EQ(p.rows, 19);
  EXPECT_EQ(p.edge_rows, 19);  // every row ends on the left edge, against the background
  for (const cone_tracker::Run& r : p.tip) {
    EXPECT_LE(r.x1, 50.0 + 0.25 * r.y) << "row " << r.y;  // pixel centres inside the right edge
    EXPECT_GE(r.x1, 50.0 + 0.25 * r.y - 1.0) << "row " << r.y;
  }
  int area = 0, rest_area = 0, all = 0;
  for (const cone_tracker::Run& r : p.tip) area += r.x1 - r.x0 + 1;
  for (const cone_tracker::Run& r : p.rest) rest_area += r.x1 - r.x0 + 1;
  for (const cone_tracker::Run& r : other) all += r.x1 - r.x0 + 1;
  // The pixels within half a pixel outside the right edge go to neither: one a row at most (the edge is this steep).
  EXPECT_LE(area + rest_area, all);
  EXPECT_GE(area + rest_area, all - 19);
  // The same pixels with orange on both sides of the wedge: no edge is seen, so no tip.
  std::vector<cone_tracker::Run> wide;
  for (int y = 2; y <= 20; ++y) wide.push_back({y, 20, 80});
  EXPECT_EQ(find(wide, fit).edge_rows, 0);
  // The image's edge is no background (cone (29).jpg of the road-cone photos: one cone cut by the left edge, its top
  // and its bottom apart across a band).
  OutlineFit cut;  // a blob cut by the image's left edge: its fitted left edge is the image's, x = -0.5
  cut.apex_undist_px = Eigen::Vector2d(-0.5, 0);
  cut.left_line = Eigen::Vector3d(1, 0, 0.5);
  cut.right_line = Eigen::Vector3d(-1, 0.25, -0.5);
  std::vector<cone_tracker::Run> from_edge;  // orange from the image's edge to x = 80
  for (int y = 2; y <= 20; ++y) from_edge.push_back({y, 0, 80});
  EXPECT_EQ(find(from_edge, cut).rows, 19);
  EXPECT_EQ(find(from_edge, cut).edge_rows, 0);
}

}  // namespace
}  // namespace cone_tracker
