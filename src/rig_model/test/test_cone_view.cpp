#include <gtest/gtest.h>

#include <optional>
#include <vector>

#include "rig_model/cone_view.h"

namespace rig_model {
namespace {

// A 40 px tall cone, 6 px half-width, with its base point at (u, v).
ConeSilhouette Triangle(double u, double v) { return {{u, v - 40.0}, {u, v}, 6.0}; }
ImageBox Cone(double u, double v) { return Triangle(u, v).Box(); }

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
  // none, two; without orange regions a cone not in plain view is never a miss, seen or not.
  const std::vector<std::optional<ConeSilhouette>> cones = {Triangle(100, 200), Triangle(300, 200), Triangle(10, 200),
                                                            std::nullopt};
  EXPECT_EQ(MissedInView(cones, {true, false, false, false}, {}, 512, 384), 1);
  EXPECT_EQ(MissedInView(cones, {}, {}, 512, 384), 2);
  EXPECT_EQ(MissedInView(cones, {true, true, true, true}, {}, 512, 384), 0);
}

TEST(ConeView, OrangeShareIsOverTheTrianglesVisibleArea) {
  const ConeSilhouette c = Triangle(200, 200);  // rows 160-200, 12 px wide at the base: 240 px^2
  double visible = 0.0;
  EXPECT_DOUBLE_EQ(OrangeShareInView(c, {Cone(200, 200)}, 512, 384, 8.0, &visible), 1.0);
  EXPECT_DOUBLE_EQ(visible, 240.0);
  EXPECT_DOUBLE_EQ(OrangeShareInView(c, {}, 512, 384, 8.0, &visible), 0.0);
  // The lower half of the rows holds three quarters of the area; the upper half a quarter.
  EXPECT_NEAR(OrangeShareInView(c, {{190, 180, 210, 200}}, 512, 384, 8.0, &visible), 0.75, 0.02);
  EXPECT_NEAR(OrangeShareInView(c, {{190, 160, 210, 180}}, 512, 384, 8.0, &visible), 0.25, 0.02);
  // Cut by the left edge (margin 8) down its axis: half of it is visible, all of that orange.
  EXPECT_NEAR(OrangeShareInView(Triangle(8, 200), {Cone(8, 200)}, 512, 384, 8.0, &visible), 1.0, 1e-12);
  EXPECT_NEAR(visible, 120.0, 10.0);
  // Wholly outside: nothing visible.
  EXPECT_DOUBLE_EQ(OrangeShareInView(Triangle(-20, 200), {}, 512, 384, 8.0, &visible), 0.0);
  EXPECT_DOUBLE_EQ(visible, 0.0);
}

TEST(ConeView, AConePartlyInViewWithNoOrangeOverItIsAMiss) {
  const std::vector<ImageBox> seen_cone = {Cone(300, 200)};  // the orange of a seen cone elsewhere
  // Cut by the left edge: a miss when no orange lies there, none when its visible part is orange.
  std::vector<std::optional<ConeSilhouette>> cones = {Triangle(300, 200), Triangle(8, 200)};
  EXPECT_EQ(MissedInView(cones, {true, false}, seen_cone, 512, 384), 1);
  EXPECT_EQ(MissedInView(cones, {true, false}, {Cone(300, 200), {0, 160, 14, 200}}, 512, 384), 0);
  // Orange over less than half of the visible part (part_max_orange_frac): still a miss.
  EXPECT_EQ(MissedInView(cones, {true, false}, {Cone(300, 200), {0, 160, 14, 180}}, 512, 384), 1);
  // Too little of it in view (part_min_area_px2): no miss.
  cones[1] = Triangle(2, 200);
  EXPECT_EQ(MissedInView(cones, {true, false}, seen_cone, 512, 384), 0);
  // Overlapping the seen cone (not in plain view): its orange covers the overlap only. Far enough apart that
  // most of the second is bare, a miss; on top of it, none.
  cones = {Triangle(300, 200), Triangle(300, 165)};
  EXPECT_EQ(MissedInView(cones, {true, false}, seen_cone, 512, 384), 1);
  cones = {Triangle(300, 200), Triangle(302, 198)};
  EXPECT_EQ(MissedInView(cones, {true, false}, seen_cone, 512, 384), 0);
}

TEST(ConeView, OrangeNearNoConeIsUnexplained) {
  // A cone with its base at (100, 100): its peak at (100, 60), 6 px to either side at the base.
  const std::vector<std::optional<ConeSilhouette>> layout = {Triangle(100.0, 100.0), std::nullopt};
  const PlainViewRule rule;  // explain_margin_px 4
  const auto count = [&](const std::vector<ImageBox>& orange, const std::vector<ConeSilhouette>& detected = {}) {
    return UnexplainedOrange(layout, detected, orange, 640.0, 480.0, rule);
  };
  EXPECT_EQ(count({{98.0, 70.0, 102.0, 80.0}}), 0);    // on the triangle
  EXPECT_EQ(count({{108.0, 96.0, 112.0, 100.0}}), 0);  // 2 px beside its base corner: within the margin
  EXPECT_EQ(count({{200.0, 70.0, 210.0, 80.0}}), 1);   // far from it
  // In the triangle's box but off the triangle: beside the apex, where the box is empty.
  EXPECT_EQ(count({{103.0 + 4.5, 55.0, 106.0 + 4.5, 62.0}}), 1);
  EXPECT_EQ(count({}), 0);
  // A detected cone explains its own orange in every reading; a quarter of its height to either side.
  const ConeSilhouette detected = DetectedSilhouette({200.0, 40.0}, {200.0, 80.0});
  EXPECT_DOUBLE_EQ(detected.half_width_px, 10.0);
  EXPECT_EQ(count({{200.0, 70.0, 210.0, 80.0}}, {detected}), 0);
  EXPECT_EQ(count({{200.0, 70.0, 210.0, 80.0}, {300.0, 70.0, 310.0, 80.0}}, {detected}), 1);
  // A box on the image's edge reaches past it: a cone just outside the image explains it (its triangle 11 px from the
  // box, beyond the margin).
  const std::vector<std::optional<ConeSilhouette>> outside = {Triangle(655.0, 100.0)};  // base corner at u = 649
  const std::vector<ImageBox> edge = {{638.5, 70.0, 639.5, 90.0}};
  EXPECT_EQ(UnexplainedOrange(outside, {}, edge, 640.0, 480.0, rule), 0);
  EXPECT_EQ(UnexplainedOrange(outside, {}, edge, 0.0, 0.0, rule), 1);  // size unknown: the box as it is
}

}  // namespace
}  // namespace rig_model
