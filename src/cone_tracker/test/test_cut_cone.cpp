// A cone cut by the image's bottom edge inside its first collar: its orange top looks like a whole,
// shorter cone (cut_cone.h). The frames are rig_sim's, cropped: the same image with fewer rows.
#include <gtest/gtest.h>

#include <algorithm>

#include "cone_tracker/testing/vision_frames.h"
#include "cone_tracker/vision/cut_cone.h"
#include "cone_tracker/vision/segmenter.h"

namespace cone_tracker {
namespace {

// The first `rows` rows of the frame: a camera whose image ends there (the intrinsics stay).
ImageView Cropped(const SimFrame& f, int rows) {
  return {f.rgb.data(), f.camera.width_px, rows, f.camera.width_px * 3, "rgb8"};
}

// The middle row of the first white run on the axis below the cone's orange tip.
int CollarRow(const SimFrame& f, const TruthCone& t) {
  const Eigen::Vector2d d = (t.base_px - t.peak_px).normalized();
  int first = -1, last = -1;
  for (double s = 2.0; s < (t.base_px - t.peak_px).norm(); s += 1.0) {
    const Eigen::Vector2d p = t.peak_px + s * d;
    const uint8_t* c = f.rgb.data() + (size_t(std::lround(p.y())) * f.camera.width_px + size_t(std::lround(p.x()))) * 3;
    const bool white = std::min({c[0], c[1], c[2]}) > 150;
    if (white && first < 0) first = int(std::lround(p.y()));
    if (!white && first >= 0) {
      last = int(std::lround(p.y()));
      break;
    }
  }
  return first >= 0 && last > first ? (first + last) / 2 : -1;
}

const ConeDetection* Near(const std::vector<ConeDetection>& cones, const Eigen::Vector2d& peak_px) {
  for (const ConeDetection& d : cones)
    if ((d.peak_px - peak_px).norm() < 4.0) return &d;
  return nullptr;
}

class CutCone : public ::testing::Test {
 protected:
  CutCone() {
    const Eigen::Vector3d eye(3.2 * std::cos(0.3), 3.2 * std::sin(0.3), 1.5);
    frame_ = RenderSim(rig_sim::DefaultScene(), LookAt(eye, Eigen::Vector3d(0, 0, 0.3)));
    // The cone whose collar is lowest in the image: the crop there keeps the others whole or out.
    for (const TruthCone& t : frame_.truth)
      if (!lowest_ || t.base_px.y() > lowest_->base_px.y()) lowest_ = &t;
  }
  SimFrame frame_;
  const TruthCone* lowest_ = nullptr;
};

TEST_F(CutCone, TopAboveACollarThatRunsOutOfTheImageFailsTheBorderGate) {
  const int row = CollarRow(frame_, *lowest_);
  ASSERT_GT(row, 0) << "no collar on the cone's axis";
  SegmenterConfig config;
  for (int contrast : {40, 0}) {
    config.cut_cone_contrast = contrast;
    Segmenter seg(config);
    const SegmentationResult r = seg.Process(Cropped(frame_, row), frame_.camera);
    ASSERT_TRUE(r.ok) << r.error;
    const ConeDetection* kept = Near(r.cones, lowest_->peak_px);
    if (contrast == 0) {  // without the test the top is taken for a whole cone: what this test is for
      EXPECT_NE(kept, nullptr) << "the uncut top no longer passes the other gates; this test shows nothing";
      continue;
    }
    EXPECT_EQ(kept, nullptr) << "the top of the cut cone was accepted, base " << kept->base_px.transpose();
    const ConeDetection* refused = Near(r.rejected, lowest_->peak_px);
    ASSERT_NE(refused, nullptr);
    EXPECT_EQ(refused->failed_gates, uint32_t(kGateBorder));
  }
}

TEST_F(CutCone, WholeConeStandingNearTheEdgeIsKept) {
  // The image ends a little below the base: ground, not a collar, runs out of the image.
  const int row = int(std::lround(lowest_->base_px.y())) + 8;
  ASSERT_LT(row, frame_.camera.height_px);
  Segmenter seg{SegmenterConfig()};
  const SegmentationResult r = seg.Process(Cropped(frame_, row), frame_.camera);
  ASSERT_TRUE(r.ok) << r.error;
  const ConeDetection* kept = Near(r.cones, lowest_->peak_px);
  ASSERT_NE(kept, nullptr);
  EXPECT_LT((kept->base_px - lowest_->base_px).norm(), 2.0);
}

TEST(CutConeTest, OffOrDegenerateInputsNeverCut) {
  const std::vector<uint8_t> grey(64 * 48 * 3, 90);
  const RgbView image{grey.data(), 64, 48, 64 * 3};
  const Eigen::Vector2d peak(32, 20), base(32, 40);
  EXPECT_FALSE(SilhouetteRunsOutOfImage(image, peak, base, 5.0, 0, 1.5));       // disabled
  EXPECT_FALSE(SilhouetteRunsOutOfImage(image, peak, base, 5.0, 40, 1.5));      // uniform ground
  EXPECT_FALSE(SilhouetteRunsOutOfImage(image, peak, peak, 5.0, 40, 1.5));      // no height
  EXPECT_FALSE(SilhouetteRunsOutOfImage(RgbView{}, peak, base, 5.0, 40, 1.5));  // no frame
}

}  // namespace
}  // namespace cone_tracker
