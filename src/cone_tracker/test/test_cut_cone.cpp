// Cones cut by the image's edge. One cut inside its first collar: its orange top looks like a whole, shorter
// cone (cut_cone.h). One whose tip alone touches the edge: measured as whole (segmenter.h, border_px). One cut
// at its base or along its side: refused. The frames are rig_sim's, cropped: the same image, fewer rows or columns.
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

// The frame from row `first` down: a camera whose image starts there (the principal point moves up with it).
struct TopCrop {
  ImageView image;
  CameraModel camera;
};
TopCrop CroppedFromTop(const SimFrame& f, int first) {
  CameraModel camera = f.camera;
  camera.cy_px -= first, camera.height_px -= first;
  const int step = f.camera.width_px * 3;
  return {{f.rgb.data() + size_t(first) * size_t(step), f.camera.width_px, camera.height_px, step, "rgb8"}, camera};
}

TEST_F(CutCone, ConeWhoseTipTouchesTheEdgeIsMeasuredAsWhole) {
  // The cone whose peak is highest in the image: the crop there cuts the tip of no other.
  const TruthCone* top = &frame_.truth[0];
  for (const TruthCone& t : frame_.truth)
    if (t.peak_px.y() < top->peak_px.y()) top = &t;
  for (int cut : {1, 2}) {
    const int first = int(std::ceil(top->peak_px.y())) + cut;
    const TopCrop crop = CroppedFromTop(frame_, first);
    Segmenter seg{SegmenterConfig()};
    const SegmentationResult r = seg.Process(crop.image, crop.camera);
    ASSERT_TRUE(r.ok) << r.error;
    const Eigen::Vector2d shift(0.0, first);
    const ConeDetection* kept = Near(r.cones, top->peak_px - shift);
    ASSERT_NE(kept, nullptr) << "cut " << cut << " px below the peak: refused";
    EXPECT_LE(kept->blob.bbox_y, SegmenterConfig().border_px) << "the blob does not reach the edge; this shows nothing";
    EXPECT_LT((kept->peak_px - (top->peak_px - shift)).norm(), 1.5) << "cut " << cut;
    EXPECT_LT((kept->base_px - (top->base_px - shift)).norm(), 1.5) << "cut " << cut;
  }
}

TEST_F(CutCone, ConeCutBeyondItsTipZoneFailsTheBorderGate) {
  const TruthCone* top = &frame_.truth[0];
  for (const TruthCone& t : frame_.truth)
    if (t.peak_px.y() < top->peak_px.y()) top = &t;
  // A fifth of the cone gone: the edge crosses where the silhouette is several pixels wide.
  const int first = int(std::lround(top->peak_px.y() + 0.2 * (top->base_px.y() - top->peak_px.y())));
  const TopCrop crop = CroppedFromTop(frame_, first);
  Segmenter seg{SegmenterConfig()};
  const SegmentationResult r = seg.Process(crop.image, crop.camera);
  ASSERT_TRUE(r.ok) << r.error;
  const Eigen::Vector2d base = top->base_px - Eigen::Vector2d(0.0, first);
  for (const ConeDetection& d : r.cones) EXPECT_GT((d.base_px - base).norm(), 4.0) << "the cut cone was accepted";
  bool refused = false;
  for (const ConeDetection& d : r.rejected)
    refused |= (d.base_px - base).norm() < 4.0 && (d.failed_gates & kGateBorder);
  EXPECT_TRUE(refused);
}

TEST_F(CutCone, ConeWhoseBaseIsCutFailsTheBorderGate) {
  // The image ends a few rows above the base: the base arc runs along the edge, a straight row that the outline's
  // parabola fits, so only the border gate knows that the base is not measured.
  for (int above : {2, 4}) {
    const int rows = int(std::lround(lowest_->base_px.y())) - above;
    Segmenter seg{SegmenterConfig()};
    const SegmentationResult r = seg.Process(Cropped(frame_, rows), frame_.camera);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(Near(r.cones, lowest_->peak_px), nullptr)
        << "the cone cut " << above << " px above its base was accepted";
    const ConeDetection* refused = Near(r.rejected, lowest_->peak_px);
    ASSERT_NE(refused, nullptr);
    EXPECT_TRUE(refused->failed_gates & kGateBorder);
  }
}

TEST_F(CutCone, ConeCutAlongItsSideFailsTheBorderGate) {
  // The leftmost cone with the left quarter of its box cut away: its apex and base stay in the image, and the image's
  // edge, a straight line, may pass for the cone's left edge in the outline fit.
  Segmenter seg{SegmenterConfig()};
  const SegmentationResult whole = seg.Process(Cropped(frame_, frame_.camera.height_px), frame_.camera);
  ASSERT_TRUE(whole.ok && !whole.cones.empty()) << whole.error;
  const ConeDetection& left = whole.cones.front();  // sorted by the peak's u
  const int first = left.blob.bbox_x + left.blob.bbox_w / 4;
  CameraModel camera = frame_.camera;
  camera.cx_px -= first, camera.width_px -= first;
  const ImageView image{frame_.rgb.data() + 3 * size_t(first), camera.width_px, camera.height_px,
                        frame_.camera.width_px * 3, "rgb8"};
  const SegmentationResult r = seg.Process(image, camera);
  ASSERT_TRUE(r.ok) << r.error;
  const Eigen::Vector2d shift(first, 0.0);
  EXPECT_EQ(Near(r.cones, left.peak_px - shift), nullptr) << "the cone cut along its side was accepted";
  int on_edge = 0;  // the cut cone's blob, whatever its line search made of it
  for (const ConeDetection& d : r.rejected)
    if (d.blob.bbox_x <= SegmenterConfig().border_px) {
      ++on_edge;
      EXPECT_TRUE(d.failed_gates & kGateBorder);
    }
  EXPECT_EQ(on_edge, 1);
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
