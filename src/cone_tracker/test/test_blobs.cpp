#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "cone_tracker/vision/blobs.h"

namespace cone_tracker {
namespace {

struct Mask {
  int w, h;
  std::vector<uint8_t> px;
  Mask(int w_, int h_) : w(w_), h(h_), px(size_t(w_) * h_, 0) {}
  void Set(int x, int y) { px[size_t(y) * w + x] = 1; }
  MaskView View() const { return {px.data(), w, h, w}; }
};

// Upright isosceles triangle, apex at (cx, top), base width `base` at y = bottom.
// Rows in [skip_from, skip_to) and [skip2_from, skip2_to) are left empty (collars).
void Triangle(Mask* m, double cx, int top, int bottom, double base, int skip_from = -1, int skip_to = -1,
              int skip2_from = -1, int skip2_to = -1) {
  for (int y = top; y <= bottom; ++y) {
    if ((y >= skip_from && y < skip_to) || (y >= skip2_from && y < skip2_to)) continue;
    const double half = 0.5 * base * (y - top) / double(bottom - top);
    for (int x = int(std::ceil(cx - half)); x <= int(std::floor(cx + half)); ++x) m->Set(x, y);
  }
}

// A cone with its apex at (ax, ay), `height` long down an axis tilted by
// tilt_deg from the image vertical (positive: base to the left), `base` wide,
// with white collars at the road cones' fractions of the height from the
// apex (0.20-0.38 and 0.45-0.58) when `collared`.
void TiltedCone(Mask* m, double ax, double ay, double height, double base, double tilt_deg, bool collared) {
  const double t = tilt_deg * M_PI / 180.0;
  const Eigen::Vector2d axis(-std::sin(t), std::cos(t)), across(axis.y(), -axis.x());
  for (int y = 0; y < m->h; ++y)
    for (int x = 0; x < m->w; ++x) {
      const Eigen::Vector2d p = Eigen::Vector2d(x, y) - Eigen::Vector2d(ax, ay);
      const double f = p.dot(axis) / height;
      if (f < 0.0 || f > 1.0 || std::abs(p.dot(across)) > 0.5 * base * f) continue;
      if (collared && ((f >= 0.20 && f < 0.38) || (f >= 0.45 && f < 0.58))) continue;
      m->Set(x, y);
    }
}

constexpr double kMaxTilt = 50.0 * M_PI / 180.0;

}  // namespace

TEST(Blobs, RectangleProperties) {
  Mask m(60, 40);
  for (int y = 10; y < 14; ++y)
    for (int x = 5; x < 25; ++x) m.Set(x, y);  // 20 x 4
  const auto blobs = FindBlobs(m.View(), 0, 0, 60, 40, 1);
  ASSERT_EQ(blobs.size(), 1u);
  const Blob& b = blobs[0];
  EXPECT_EQ(b.area, 80);
  EXPECT_NEAR(b.centroid.x(), 14.5, 1e-12);
  EXPECT_NEAR(b.centroid.y(), 11.5, 1e-12);
  // regionprops: the ellipse with the same second moments as a 20x4 box
  // has axes 20*2/sqrt(3) and 4*2/sqrt(3).
  EXPECT_NEAR(b.major_px, 40.0 / std::sqrt(3.0), 1e-9);
  EXPECT_NEAR(b.minor_px, 8.0 / std::sqrt(3.0), 1e-9);
  EXPECT_NEAR(b.orientation_rad, 0.0, 1e-12);
  EXPECT_NEAR(b.solidity, 1.0, 1e-6);
  EXPECT_EQ(b.bbox_x, 5);
  EXPECT_EQ(b.bbox_w, 20);
  EXPECT_EQ(b.bbox_h, 4);
}

TEST(Blobs, BlobOfRunsSumsTheHullsOfItsPieces) {
  // Two 10x10 squares a band apart: the hull of each, not of both.
  std::vector<cone_tracker::Run> runs;
  for (int y = 0; y < 10; ++y) runs.push_back({y, 0, 9}), runs.push_back({y + 15, 0, 9});
  const Blob b = BlobOfRuns(runs);
  EXPECT_EQ(b.fragments, 2);
  EXPECT_DOUBLE_EQ(b.hull_area, 200.0);
  EXPECT_DOUBLE_EQ(b.area, 200.0);
  EXPECT_DOUBLE_EQ(b.solidity, 1.0);
  EXPECT_EQ(b.bbox_h, 25);
  // Touching diagonally: one piece (8-connected).
  const Blob c = BlobOfRuns({{0, 0, 4}, {1, 5, 9}});
  EXPECT_EQ(c.fragments, 1);
}

TEST(Blobs, RowSlabsTileTheRowsAndFollowTheWidening) {
  // A cone of 40 rows (10-49) with two collars (rows 20-26 and 30-39), its pieces taken as one blob: four bands of
  // 10 rows each, the collars' rows covered.
  Mask m(100, 60);
  Triangle(&m, 50.0, 10, 49, 24.0, 20, 27, 30, 40);
  std::vector<cone_tracker::Run> runs;
  for (const Blob& b : FindBlobs(m.View(), 0, 0, 100, 60, 1)) runs.insert(runs.end(), b.runs.begin(), b.runs.end());
  const std::vector<rig_model::ImageBox> slabs = RowSlabs(runs, 4);
  ASSERT_EQ(slabs.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_DOUBLE_EQ(slabs[i].v_min, 9.5 + 10.0 * double(i));
    EXPECT_DOUBLE_EQ(slabs[i].v_max, 19.5 + 10.0 * double(i));
  }
  EXPECT_LT(slabs[0].u_max - slabs[0].u_min, 8.0);  // the tip: rows 10-19, up to 6 px wide
  EXPECT_EQ(slabs[2].u_min, slabs[3].u_min);        // rows 30-39 are all collar: the band below's columns
  EXPECT_EQ(slabs[2].u_max, slabs[3].u_max);
  EXPECT_GT(slabs[3].u_max - slabs[3].u_min, 20.0);  // the base
  // Fewer rows than bands: one band per row; no runs, no bands.
  EXPECT_EQ(RowSlabs({{5, 0, 3}, {6, 0, 4}}, 4).size(), 2u);
  EXPECT_TRUE(RowSlabs({}, 4).empty());
}

TEST(Blobs, DiagonalNeighboursAreOneBlobAndRoiClips) {
  Mask m(10, 10);
  m.Set(2, 2), m.Set(3, 3), m.Set(4, 4), m.Set(8, 1), m.Set(0, 9);
  auto blobs = FindBlobs(m.View(), 0, 0, 10, 10, 1);
  ASSERT_EQ(blobs.size(), 3u);
  std::sort(blobs.begin(), blobs.end(), [](const Blob& a, const Blob& b) { return a.area > b.area; });
  EXPECT_NEAR(blobs[0].orientation_rad, M_PI / 4.0, 1e-9);  // v down: +45 deg
  blobs = FindBlobs(m.View(), 0, 0, 10, 10, 2);             // artifacts dropped
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_EQ(blobs[0].area, 3);
  blobs = FindBlobs(m.View(), 3, 0, 10, 5, 1);  // ROI excludes (2, 2)
  ASSERT_EQ(blobs.size(), 2u);
  EXPECT_TRUE(FindBlobs(Mask(5, 5).View(), 0, 0, 5, 5, 1).empty());
}

TEST(Blobs, ConcaveShapeHasLowSolidity) {
  Mask m(40, 40);
  for (int i = 5; i < 35; ++i) m.Set(i, 5), m.Set(5, i);  // an L of thin lines
  const auto blobs = FindBlobs(m.View(), 0, 0, 40, 40, 1);
  ASSERT_EQ(blobs.size(), 1u);
  EXPECT_LT(blobs[0].solidity, 0.2);
}

TEST(Blobs, CollarFragmentsMergeAlongTheAxisButSideBySideConesDoNot) {
  Mask m(200, 200);
  // A cone 100 px tall split by two collars (0.42-0.55 and 0.62-0.80 of the
  // height above the base, as the road cones), and an unsplit cone beside it.
  Triangle(&m, 50, 50, 150, 28, 50 + 20, 50 + 38, 50 + 45, 50 + 58);
  Triangle(&m, 120, 50, 150, 28);
  auto blobs = FindBlobs(m.View(), 0, 0, 200, 200, 4);
  ASSERT_EQ(blobs.size(), 4u);
  MergeAlongAxes(&blobs, 0.25, 0.5, kMaxTilt);
  ASSERT_EQ(blobs.size(), 2u);
  for (const Blob& b : blobs) {
    EXPECT_NEAR(std::abs(b.orientation_rad), M_PI / 2.0, 0.02);
    EXPECT_EQ(b.bbox_h, 101);
  }
  EXPECT_EQ(blobs[0].fragments + blobs[1].fragments, 4);
}

TEST(Blobs, ConeStandingBehindAnotherIsNotMerged) {
  Mask m(200, 260);
  Triangle(&m, 60, 130, 230, 28);  // near cone
  Triangle(&m, 60, 40, 110, 20);   // far cone, seen just above the near one's peak
  auto blobs = FindBlobs(m.View(), 0, 0, 200, 260, 4);
  ASSERT_EQ(blobs.size(), 2u);
  MergeAlongAxes(&blobs, 0.25, 0.5, kMaxTilt);
  EXPECT_EQ(blobs.size(), 2u);
}

TEST(Blobs, TiltedCollaredConeMergesIntoOne) {
  // Lens distortion near the image edge and the rig's roll tilt cones in the
  // image; the squat body below the collars must still find its band and tip.
  for (double tilt : {-30.0, -15.0, 15.0, 30.0}) {
    Mask m(200, 200);
    TiltedCone(&m, 100, 30, 140, 56, tilt, true);
    auto blobs = FindBlobs(m.View(), 0, 0, 200, 200, 4);
    ASSERT_EQ(blobs.size(), 3u) << tilt;
    MergeAlongAxes(&blobs, 0.25, 0.5, kMaxTilt);
    ASSERT_EQ(blobs.size(), 1u) << tilt;
    EXPECT_EQ(blobs[0].fragments, 3);
    // The whole cone's major axis is its axis (v down: orientation -90 + tilt... folded into (-90, 90]).
    EXPECT_NEAR(std::abs(std::cos(blobs[0].orientation_rad)), std::abs(std::sin(tilt * M_PI / 180.0)), 0.03) << tilt;
  }
}

TEST(Blobs, TiltBeyondTheGateDoesNotMerge) {
  Mask m(240, 240);
  TiltedCone(&m, 60, 40, 140, 56, -70.0, true);  // lying on its side
  auto blobs = FindBlobs(m.View(), 0, 0, 240, 240, 4);
  const size_t before = blobs.size();
  ASSERT_EQ(before, 3u);
  MergeAlongAxes(&blobs, 0.25, 0.5, kMaxTilt);
  EXPECT_EQ(blobs.size(), before);
}

TEST(Blobs, FarConeAboveACollaredConesTipStaysApart) {
  // The near cone's three fragments join each other, nearest first, and the
  // far cone seen just above the near one's tip keeps to itself.
  Mask m(200, 300);
  TiltedCone(&m, 100, 120, 170, 64, 0.0, true);  // near, collared
  TiltedCone(&m, 100, 50, 66, 26, 0.0, false);   // far, its base 4 px above the near apex
  auto blobs = FindBlobs(m.View(), 0, 0, 200, 300, 4);
  ASSERT_EQ(blobs.size(), 4u);
  MergeAlongAxes(&blobs, 0.25, 0.5, kMaxTilt);
  ASSERT_EQ(blobs.size(), 2u);
  EXPECT_EQ(blobs[0].fragments + blobs[1].fragments, 4);
  for (const Blob& b : blobs) EXPECT_TRUE(b.fragments == 3 || b.bbox_y == 50) << b.fragments << " " << b.bbox_y;
}

}  // namespace cone_tracker
