#include <gtest/gtest.h>

#include "rig_model/cone_view.h"

namespace rig_model {
namespace {

// A 40 px tall cone, 6 px half-width, with its base point at (u, v).
ImageBox Cone(double u, double v) { return SilhouetteBox({u, v - 40.0}, {u, v}, 6.0); }

TEST(ConeView, SilhouetteBoxSpansPeakBaseAndHalfWidth) {
  const ImageBox b = SilhouetteBox({100.0, 50.0}, {104.0, 90.0}, 5.0);
  EXPECT_DOUBLE_EQ(b.u_min, 95.0);
  EXPECT_DOUBLE_EQ(b.u_max, 109.0);
  EXPECT_DOUBLE_EQ(b.v_min, 50.0);
  EXPECT_DOUBLE_EQ(b.v_max, 90.0);
  EXPECT_DOUBLE_EQ(b.height(), 40.0);
}

TEST(ConeView, PlainViewNeedsTheWholeSilhouetteInsideTallAndApart) {
  const PlainViewRule rule;  // 8 px margin, 12 px tall
  // In the middle; against the left edge (a cut cone is no miss); behind the camera; tiny.
  std::vector<std::optional<ImageBox>> boxes = {Cone(200, 200), Cone(10, 200), std::nullopt,
                                                SilhouetteBox({300, 100}, {300, 108}, 1.0)};
  std::vector<bool> plain = InPlainView(boxes, 512, 384, rule);
  EXPECT_EQ(plain, (std::vector<bool>{true, false, false, false}));
  // Exactly at the margin is inside; a pixel further is not.
  boxes = {Cone(8.0 + 6.0, 200)};
  EXPECT_TRUE(InPlainView(boxes, 512, 384, rule)[0]);
  boxes = {Cone(7.0 + 6.0, 200)};
  EXPECT_FALSE(InPlainView(boxes, 512, 384, rule)[0]);
  boxes = {Cone(200, 384 - 1 - 8)};
  EXPECT_TRUE(InPlainView(boxes, 512, 384, rule)[0]);
  // Two overlapping silhouettes (one hides or merges with the other): neither; a cone beside them
  // stays in plain view, and a cone behind the camera hides nothing.
  boxes = {Cone(200, 200), Cone(205, 210), Cone(300, 200), std::nullopt};
  plain = InPlainView(boxes, 512, 384, rule);
  EXPECT_EQ(plain, (std::vector<bool>{false, false, true, false}));
  // A cone just outside the image still hides the one it overlaps.
  boxes = {Cone(10, 200), Cone(20, 200)};
  EXPECT_EQ(InPlainView(boxes, 512, 384, rule), (std::vector<bool>{false, false}));
}

TEST(ConeView, MissesAreConesInPlainViewNotSeen) {
  // Two in plain view, one cut by the edge, one behind the camera: seeing the first leaves one miss; seeing
  // none, two; a cone not in plain view is never a miss, seen or not.
  const std::vector<std::optional<ImageBox>> boxes = {Cone(100, 200), Cone(300, 200), Cone(10, 200), std::nullopt};
  EXPECT_EQ(MissedInPlainView(boxes, {true, false, false, false}, 512, 384), 1);
  EXPECT_EQ(MissedInPlainView(boxes, {}, 512, 384), 2);
  EXPECT_EQ(MissedInPlainView(boxes, {true, true, true, true}, 512, 384), 0);
}

}  // namespace
}  // namespace rig_model
