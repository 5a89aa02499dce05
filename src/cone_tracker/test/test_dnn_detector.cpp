// The learned cone detector (vision/dnn_detector.h, vision/cone_detector.h): errors that name the
// model file, decoding and NMS on a synthetic network output, and the committed model on the TraCon
// development photos (../shared/data/images/tracon_train; skipped with a message when absent).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <dirent.h>

#include <opencv2/imgcodecs.hpp>

#include "cone_tracker/node/params.h"
#include "cone_tracker/vision/cone_detector.h"
#include "rig_model/strict_yaml.h"
#include "test_files.h"

namespace cone_tracker {
namespace {

TEST(DnnDetector, MissingModelIsAnErrorNamingTheFile) {
  DnnDetectorConfig c;
  c.model_file = "/tmp/cone_tracker_dnn_test_no_such_model.onnx";
  const std::string e = ErrorOf([&] { DnnDetector d(c); });
  EXPECT_NE(e.find(c.model_file), std::string::npos) << e;
  EXPECT_NE(e.find("cannot open"), std::string::npos) << e;
}

TEST(DnnDetector, UnloadableModelIsAnErrorNamingTheFile) {
  DnnDetectorConfig c;
  c.model_file = "/tmp/cone_tracker_dnn_test_garbage.onnx";
  std::ofstream(c.model_file) << "this is not an ONNX model\n";
  const std::string e = ErrorOf([&] { DnnDetector d(c); });
  std::remove(c.model_file.c_str());
  EXPECT_NE(e.find(c.model_file), std::string::npos) << e;
  EXPECT_NE(e.find("not a model OpenCV can load"), std::string::npos) << e;
}

TEST(DnnDetector, BadConfigNamesTheParameter) {
  ConeDetectorConfig c;
  c.detector = 2;
  EXPECT_NE(c.Validate().find("detector"), std::string::npos);
  c = ConeDetectorConfig();
  c.dnn_score_min = 1.5;
  EXPECT_NE(ErrorOf([&] { ConeDetector d(SegmenterConfig(), c); }).find("dnn_score_min"), std::string::npos);
  c = ConeDetectorConfig();
  c.detector = static_cast<int>(DetectorKind::kDnn);
  c.dnn_model = "/tmp/cone_tracker_dnn_test_missing.onnx";
  EXPECT_NE(ErrorOf([&] { ConeDetector d(SegmenterConfig(), c); }).find(c.dnn_model), std::string::npos);
}

// A synthetic 5 x 8 x 8 output: two cones, a weaker neighbour of one peak (not a local maximum), a
// lower peak whose box overlaps the second (NMS), and a peak below the threshold. Sizes in cells.
TEST(DnnDetector, DecodesPeaksSizesOffsetsAndSuppressesOverlaps) {
  const int g = 8;
  const double s = kDnnStride;  // input pixels per cell
  std::vector<float> heads(kDnnChannels * g * g, 0.0f);
  auto set = [&](int x, int y, float heat, double w_cells, double h_cells, float ox, float oy) {
    const int i = y * g + x;
    heads[i] = heat;
    heads[g * g + i] = float(std::log(w_cells)), heads[2 * g * g + i] = float(std::log(h_cells));
    heads[3 * g * g + i] = ox, heads[4 * g * g + i] = oy;
  };
  set(2, 3, 0.9f, 2.0, 4.0, 0.5f, 0.25f);  // centre (2.5, 3.25) cells
  set(3, 3, 0.6f, 2.0, 4.0, 0.5f, 0.5f);   // its neighbour: not a peak
  set(6, 6, 0.7f, 1.0, 3.0, 0.0f, 0.0f);   // a second cone, centre (6, 6)
  set(6, 4, 0.5f, 1.0, 3.0, 0.0f, 1.5f);   // centre (6, 5.5): overlaps the second by IoU 0.71
  set(0, 7, 0.2f, 1.0, 1.0, 0.0f, 0.0f);   // below score_min
  const double scale = 0.5;                // input pixels per image pixel
  const std::vector<DnnBox> boxes = DecodeDnnHeads(heads.data(), g, g, scale, 1000, 1000, 0.3, 0.5);
  ASSERT_EQ(boxes.size(), 2u);
  EXPECT_FLOAT_EQ(boxes[0].score, 0.9f);
  EXPECT_NEAR(boxes[0].x, (2.5 - 1.0) * s / scale, 1e-4);
  EXPECT_NEAR(boxes[0].y, (3.25 - 2.0) * s / scale, 1e-4);
  EXPECT_NEAR(boxes[0].w, 2.0 * s / scale, 1e-4);
  EXPECT_NEAR(boxes[0].h, 4.0 * s / scale, 1e-4);
  EXPECT_FLOAT_EQ(boxes[1].score, 0.7f);
  EXPECT_NEAR(boxes[1].x, 5.5 * s / scale, 1e-4);
  EXPECT_NEAR(boxes[1].h, 3.0 * s / scale, 1e-4);
  // With a looser NMS the overlapping peak survives; boxes are clipped to the image.
  EXPECT_EQ(DecodeDnnHeads(heads.data(), g, g, scale, 1000, 1000, 0.3, 0.8).size(), 3u);
  const double edge = 3.0 * s;  // an image 3 cells wide and high
  const std::vector<DnnBox> clipped = DecodeDnnHeads(heads.data(), g, g, 1.0, int(edge), int(edge), 0.3, 0.5);
  ASSERT_EQ(clipped.size(), 1u);  // the second cone's centre is outside
  EXPECT_NEAR(clipped[0].x + clipped[0].w, std::min(edge, 3.5 * s), 1e-4);
  EXPECT_NEAR(clipped[0].y + clipped[0].h, edge, 1e-4);
}

TEST(DnnDetector, OverlapOfBoxes) {
  EXPECT_DOUBLE_EQ(BoxIou({0, 0, 2, 2, 1}, {1, 0, 2, 2, 1}), 2.0 / 6.0);
  EXPECT_DOUBLE_EQ(BoxIou({0, 0, 2, 2, 1}, {5, 5, 2, 2, 1}), 0.0);
  const std::vector<DnnBox> kept =
      SuppressOverlaps({{0, 0, 10, 10, 0.5}, {1, 0, 10, 10, 0.8}, {20, 0, 5, 5, 0.1}}, 0.5);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_DOUBLE_EQ(kept[0].score, 0.8);
  EXPECT_DOUBLE_EQ(kept[1].score, 0.1);
}

// A striped cone boxed twice (its upper band, scored higher, and the whole cone): one box, the whole
// cone's, with the higher score. A box inside but off the cone's axis, one only partly inside, and a
// separate cone stay.
TEST(DnnDetector, MergesABoxThatIsPartOfALargerConesBox) {
  const DnnBox whole{100, 100, 60, 200, 0.75}, band{112, 105, 40, 90, 0.83};
  const DnnBox off_axis{140, 200, 20, 60, 0.6};   // centre x 150, the whole cone's 130: 20 > 0.25 x 60
  const DnnBox partly{120, 40, 20, 100, 0.5};     // 40 % of its area inside
  const DnnBox elsewhere{400, 100, 30, 90, 0.9};  // another cone
  const std::vector<DnnBox> merged = MergeContainedBoxes({band, whole, off_axis, partly, elsewhere}, 0.7, 0.1);
  ASSERT_EQ(merged.size(), 4u);
  EXPECT_DOUBLE_EQ(merged[0].score, 0.9);  // score order
  EXPECT_DOUBLE_EQ(merged[1].score, 0.83);
  EXPECT_DOUBLE_EQ(merged[1].x, whole.x);
  EXPECT_DOUBLE_EQ(merged[1].y, whole.y);
  EXPECT_DOUBLE_EQ(merged[1].w, whole.w);
  EXPECT_DOUBLE_EQ(merged[1].h, whole.h);
  EXPECT_DOUBLE_EQ(merged[2].score, 0.6);
  EXPECT_DOUBLE_EQ(merged[3].score, 0.5);
  // The band box would pass NMS (IoU 0.3 with the whole cone): the containment rule is what merges it.
  EXPECT_LT(BoxIou(band, whole), 0.5);
  EXPECT_EQ(SuppressOverlaps({band, whole}, 0.5).size(), 2u);
  // A looser axis keeps fewer; contain_frac above 1 merges nothing.
  EXPECT_EQ(MergeContainedBoxes({band, whole, off_axis, partly, elsewhere}, 0.7, 0.5).size(), 3u);
  EXPECT_EQ(MergeContainedBoxes({band, whole, off_axis, partly, elsewhere}, 1.01, 0.1).size(), 5u);
  // The defaults are these (chosen on the development photos' training split, README).
  EXPECT_DOUBLE_EQ(DnnDetectorConfig().contain_frac, 0.7);
  EXPECT_DOUBLE_EQ(DnnDetectorConfig().contain_axis_frac, 0.1);
  DnnDetectorConfig c;
  c.model_file = "x.onnx";
  c.contain_frac = 0.0;
  EXPECT_NE(c.Validate().find("contain_frac must be > 0"), std::string::npos);
}

// Two views' boxes: a cone seen in both (mean box, mean score), one seen only in the image (half its
// score: below 0.4, kept at 0.2), one only in the mirror image.
TEST(DnnDetector, FusesTheImageAndItsMirrorImage) {
  const DnnBox both_a{100, 100, 40, 80, 0.8}, both_b{104, 100, 40, 84, 0.6};
  const DnnBox image_only{300, 100, 20, 40, 0.5}, mirror_only{500, 50, 30, 60, 0.9};
  std::vector<DnnBox> fused = FuseMirroredViews({both_a, image_only}, {mirror_only, both_b}, 0.4);
  ASSERT_EQ(fused.size(), 2u);
  EXPECT_DOUBLE_EQ(fused[0].score, 0.7);
  EXPECT_DOUBLE_EQ(fused[0].x, 102);
  EXPECT_DOUBLE_EQ(fused[0].w, 40);
  EXPECT_DOUBLE_EQ(fused[0].h, 82);
  EXPECT_DOUBLE_EQ(fused[1].score, 0.45);
  EXPECT_DOUBLE_EQ(fused[1].x, 500);
  fused = FuseMirroredViews({both_a, image_only}, {mirror_only, both_b}, 0.2);
  ASSERT_EQ(fused.size(), 3u);
  EXPECT_DOUBLE_EQ(fused[2].score, 0.25);
  EXPECT_TRUE(FuseMirroredViews({}, {}, 0.1).empty());
}

// ---- the committed model on the development photos, through photos.yaml as detect_cones reads it

std::string TraconDir() {
  return SharedDataDir("images/tracon_train", "images/cone (1).jpg", "CONE_TRACKER_TRACON_DIR");
}

struct Box {
  double x, y, w, h;
};

std::vector<Box> Labels(const std::string& file, int width, int height) {
  std::vector<Box> boxes;
  std::ifstream in(file);
  int cls;
  double cx, cy, w, h;
  while (in >> cls >> cx >> cy >> w >> h)
    boxes.push_back({(cx - w / 2) * width, (cy - h / 2) * height, w * width, h * height});
  return boxes;
}

double Iou(const Box& a, const Box& b) { return BoxIou({a.x, a.y, a.w, a.h, 0}, {b.x, b.y, b.w, b.h, 0}); }

// The committed model with photos.yaml measures precision 0.836 and recall 0.822 on all 399 development
// photos (README) and 0.849 / 0.827 on the every-4th subset this test scores (TP 129, FP 23, FN 27); the
// bounds are the goal for them, 0.8 each, so a worse model or a broken pre/post-processing (the
// mirror-image fusion, the containment merge) fails.
constexpr double kMinPrecision = 0.80, kMinRecall = 0.80;

// The committed model on a photo and on its mirror image: the same cones, mirrored (the mirror
// view's boxes are mapped back into the image correctly, and the fusion treats both views alike).
TEST(DnnDetector, MirrorImageGivesMirroredBoxes) {
  const std::string dir = TraconDir();
  if (dir.empty()) GTEST_SKIP() << "../shared/data/images/tracon_train not found: real-photo test skipped";
  const cv::Mat bgr = cv::imread(dir + "/images/cone (1).jpg", cv::IMREAD_COLOR);
  ASSERT_FALSE(bgr.empty());
  cv::Mat mirrored;
  cv::flip(bgr, mirrored, 1);
  DnnDetectorConfig c;
  c.model_file = DefaultDnnModelFile();
  DnnDetector detector(c);
  const std::vector<DnnBox> boxes = detector.Detect(bgr), back = detector.Detect(mirrored);
  ASSERT_FALSE(boxes.empty());
  ASSERT_EQ(boxes.size(), back.size());
  for (const DnnBox& b : boxes) {
    double best = 0.0;
    for (const DnnBox& m : back) best = std::max(best, BoxIou(b, {bgr.cols - m.x - m.w, m.y, m.w, m.h, m.score}));
    EXPECT_GT(best, 0.9) << b.x << " " << b.y << " " << b.w << " " << b.h;
  }
}

TEST(DnnDetector, FindsTheConesOfTheDevelopmentPhotos) {
  const std::string dir = TraconDir();
  if (dir.empty()) GTEST_SKIP() << "../shared/data/images/tracon_train not found: real-photo test skipped";
  const std::string yaml = std::string(CONE_TRACKER_SOURCE_DIR) + "/config/photos.yaml";
  const NodeConfig config = LoadConfigFile(yaml);  // as detect_cones reads it
  ASSERT_EQ(config.detector.kind(), DetectorKind::kDnn) << yaml;
  ConeDetector detector(config.segmenter, config.detector);

  std::vector<std::string> names;
  DIR* d = opendir((dir + "/images").c_str());
  ASSERT_NE(d, nullptr);
  while (dirent* e = readdir(d))
    if (e->d_name[0] != '.') names.push_back(e->d_name);
  closedir(d);
  ASSERT_GT(names.size(), 300u);
  // Every 4th photo by name (100 of 399): two network passes a photo, the whole set takes ~50 s of
  // `make test`; the whole set is `make eval-photos`'s (README, "Learned detector for photos").
  std::sort(names.begin(), names.end());
  for (size_t k = 0; k < names.size(); k += 4) names[k / 4] = names[k];
  names.resize((names.size() + 3) / 4);
  int tp = 0, fp = 0, fn = 0, box_points = 0;
  for (const std::string& name : names) {
    const cv::Mat bgr = cv::imread(dir + "/images/" + name, cv::IMREAD_COLOR);
    ASSERT_FALSE(bgr.empty()) << name;
    const std::vector<Box> truth =
        Labels(dir + "/labels/" + name.substr(0, name.rfind('.')) + ".txt", bgr.cols, bgr.rows);
    const ConeDetectorResult r = detector.Process({bgr.data, bgr.cols, bgr.rows, int(bgr.step), "bgr8"}, CameraModel());
    ASSERT_TRUE(r.segmentation.ok) << name << ": " << r.segmentation.error;
    ASSERT_EQ(r.scores.size(), r.segmentation.cones.size());
    std::vector<bool> used(truth.size(), false);
    for (size_t k = 0; k < r.segmentation.cones.size(); ++k) {  // greedy, in score order
      const ConeDetection& c = r.segmentation.cones[k];
      const Box b{double(c.blob.bbox_x), double(c.blob.bbox_y), double(c.blob.bbox_w), double(c.blob.bbox_h)};
      if (!r.points_from_colour[k]) {  // the box's points: apex top centre, base bottom centre
        ++box_points;
        EXPECT_NEAR(c.peak_px.x(), b.x + b.w / 2, 1.0) << name;
        EXPECT_NEAR(c.peak_px.y(), b.y, 1.0) << name;
        EXPECT_NEAR(c.base_px.y(), b.y + b.h, 1.0) << name;
      }
      int best = -1;
      double best_iou = 0;
      for (size_t j = 0; j < truth.size(); ++j)
        if (!used[j] && Iou(b, truth[j]) > best_iou) best = int(j), best_iou = Iou(b, truth[j]);
      if (best_iou >= 0.5) {
        ++tp;
        used[best] = true;
      } else {
        ++fp;
      }
    }
    for (bool u : used) fn += u ? 0 : 1;
  }
  const double precision = tp / std::max(1.0, double(tp + fp)), recall = tp / std::max(1.0, double(tp + fn));
  std::printf("%zu photos: TP %d FP %d FN %d precision %.3f recall %.3f (%d cones with the box's points)\n",
              names.size(), tp, fp, fn, precision, recall, box_points);
  // The goal, a little below what the committed model measures (README, "Learned detector for photos").
  EXPECT_GE(precision, kMinPrecision);
  EXPECT_GE(recall, kMinRecall);
}

}  // namespace
}  // namespace cone_tracker
