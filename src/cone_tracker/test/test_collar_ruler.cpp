// Cones cut at their base by the image's edge, read by their collars (collar_ruler.h). The frames are rig_sim's,
// cropped: the same image, fewer rows (test_cut_cone.cpp has the border gate's side of the same crops).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "cone_tracker/testing/vision_frames.h"
#include "cone_tracker/vision/collar_ruler.h"
#include "cone_tracker/vision/cone_pose.h"
#include "cone_tracker/vision/segmenter.h"

namespace cone_tracker {
namespace {

// The first `rows` rows of the frame (the intrinsics stay).
ImageView TopRows(const SimFrame& f, int rows) {
  return {f.rgb.data(), f.camera.width_px, rows, f.camera.width_px * 3, "rgb8"};
}

class CollarRuler : public ::testing::Test {
 protected:
  CollarRuler() {
    const Eigen::Vector3d eye(3.2 * std::cos(0.3), 3.2 * std::sin(0.3), 1.5);
    frame_ = RenderSim(rig_sim::DefaultScene(), LookAt(eye, Eigen::Vector3d(0, 0, 0.3)));
    for (const TruthCone& t : frame_.truth)  // the cone whose base is lowest in the image: a crop cuts it alone
      if (!lowest_ || t.base_px.y() > lowest_->base_px.y()) lowest_ = &t;
    config_.collar.collars = CommonCollars(ConeModels(rig_sim::DefaultScene()));
  }
  // The row `frac` of the lowest cone's height above its base (the crop keeps the rows above it).
  int RowAbove(double frac) const {
    return int(std::lround(lowest_->base_px.y() - frac * (lowest_->base_px.y() - lowest_->peak_px.y())));
  }
  const ConeDetection* ReadCone(const SegmentationResult& r) const {
    for (const ConeDetection& d : r.cones)
      if (d.by_collars && (d.peak_px - lowest_->peak_px).norm() < 4.0) return &d;
    return nullptr;
  }
  SimFrame frame_;
  const TruthCone* lowest_ = nullptr;
  SegmenterConfig config_;
};

TEST_F(CollarRuler, TheLayoutHasCollars) { ASSERT_EQ(config_.collar.collars.size(), 2u); }

TEST_F(CollarRuler, AConeCutBelowItsCollarsIsReadByThem) {
  Segmenter seg(config_);
  for (double frac : {0.05, 0.15, 0.3}) {  // the lower collar's bottom is at 0.42 of the height
    const int rows = RowAbove(frac);
    const SegmentationResult r = seg.Process(TopRows(frame_, rows), frame_.camera);
    ASSERT_TRUE(r.ok) << r.error;
    const ConeDetection* d = ReadCone(r);
    ASSERT_NE(d, nullptr) << "cut at " << frac << " of the height: not read";
    const double peak_err = (d->peak_px - lowest_->peak_px).norm(), base_err = (d->base_px - lowest_->base_px).norm();
    std::printf(
        "[ collars ] cut at %.2f of the height (%d rows): peak %.2f px, base %.2f px off (%.1f px past the "
        "edge), sigma along the axis peak %.2f, base %.2f px\n",
        frac, rows, peak_err, base_err, lowest_->base_px.y() - rows, d->axis_sigma_px(0), d->axis_sigma_px(2));
    EXPECT_LT(peak_err, 1.0);
    EXPECT_LT(base_err, 1.5);
    EXPECT_GT(lowest_->base_px.y(), rows - 1.0);  // the base is past the edge: what the border gate refuses
    EXPECT_GT(d->axis_sigma_px(2), 0.0);
  }
}

TEST_F(CollarRuler, WithoutTheLayoutsCollarsACutConeStaysRefused) {
  for (bool read : {true, false}) {
    SegmenterConfig c = config_;
    if (read)
      c.collar.collars.clear();
    else
      c.read_collars = false;
    Segmenter seg(c);
    const SegmentationResult r = seg.Process(TopRows(frame_, RowAbove(0.15)), frame_.camera);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(ReadCone(r), nullptr);
    for (const ConeDetection& d : r.cones) EXPECT_GT((d.peak_px - lowest_->peak_px).norm(), 4.0);
  }
}

TEST_F(CollarRuler, ACutThroughTheCollarsIsNotRead) {
  // Inside the lower collar, or above it: three edges or fewer, not enough for the map and a check.
  Segmenter seg(config_);
  for (double frac : {0.48, 0.58}) {
    const SegmentationResult r = seg.Process(TopRows(frame_, RowAbove(frac)), frame_.camera);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(ReadCone(r), nullptr) << "cut at " << frac;
  }
}

TEST_F(CollarRuler, AWholeConeIsMeasuredByItsOutline) {
  Segmenter with(config_), without{SegmenterConfig()};
  const ImageView whole = TopRows(frame_, frame_.camera.height_px);
  const SegmentationResult a = with.Process(whole, frame_.camera), b = without.Process(whole, frame_.camera);
  ASSERT_TRUE(a.ok && b.ok);
  ASSERT_EQ(a.cones.size(), b.cones.size());
  for (size_t i = 0; i < a.cones.size(); ++i) {
    EXPECT_FALSE(a.cones[i].by_collars);
    EXPECT_EQ(a.cones[i].base_px, b.cones[i].base_px);
  }
}

TEST(CollarRulerConfig, CollarsMustBeDisjointFractions) {
  CollarRulerConfig c;
  EXPECT_EQ(c.Validate(), "");
  c.collars = {{0.42, 0.55}, {0.62, 0.80}};
  EXPECT_EQ(c.Validate(), "");
  for (const auto& bad : std::vector<std::vector<std::pair<double, double>>>{
           {{0.55, 0.42}}, {{0.42, 0.65}, {0.62, 0.80}}, {{0.0, 0.2}}, {{0.8, 1.0}}}) {
    c.collars = bad;
    EXPECT_NE(c.Validate().find("collars"), std::string::npos);
  }
}

TEST(ReadCollars, AnAxisThatStartsOffTheConeReadsNothing) {
  const std::vector<uint8_t> grey(64 * 48 * 3, 90);  // ground: no orange anywhere
  CollarRulerConfig c;
  c.collars = {{0.42, 0.55}, {0.62, 0.80}};
  const CollarReading r =
      ReadCollars(RgbView{grey.data(), 64, 48, 64 * 3}, CameraModel(), {32, 5}, {0, 1}, 2.0, false, c);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.why.find("orange"), std::string::npos) << r.why;
}

}  // namespace
}  // namespace cone_tracker
