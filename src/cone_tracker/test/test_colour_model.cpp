// The learned colour table (colour_model.h), the merging of a striped cone's fragments across white
// bands, and the cone-silhouette check (cone_shape.h), on synthetic images.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "cone_tracker/vision/colour_model.h"
#include "cone_tracker/vision/segmenter.h"
#include "rig_model/strict_yaml.h"

namespace cone_tracker {
namespace {

std::string TempPath(const std::string& name) {
  return ::testing::TempDir() + "cone_tracker_colour_" + std::to_string(getpid()) + "_" + name;
}

// A 16-bin model: cone where r is in the top four bins and b in the bottom two.
std::string ModelText(const std::string& threshold_key = "threshold", int bytes = 16 * 16 * 16) {
  std::string hex;
  for (int i = 0; i < bytes; ++i) {
    const int r = i / 256, b = i % 16;
    const int8_t v = (r >= 12 && b <= 1) ? 40 : -40;
    char buf[3];
    std::snprintf(buf, sizeof buf, "%02x", uint8_t(v));
    hex += buf;
  }
  return "format: cone_colour_model\nbins_per_channel: 16\nllr_scale: 0.125\n" + threshold_key + ": 1.0\nllr: \"" +
         hex + "\"\n";
}

std::string Write(const std::string& name, const std::string& text) {
  const std::string path = TempPath(name);
  std::ofstream(path) << text;
  return path;
}

std::string LoadError(const std::string& path) {
  try {
    LoadColourModel(path);
  } catch (const rig_model::FileError& e) {
    return e.what();
  }
  return "";
}

TEST(ColourModel, GoodFileFillsTheTable) {
  const std::string path = Write("good.yaml", ModelText());
  const ColourModel m = LoadColourModel(path);
  EXPECT_EQ(m.bins_per_channel, 16);
  EXPECT_TRUE(m.IsCone(250, 100, 10));
  EXPECT_FALSE(m.IsCone(250, 100, 40));  // b in the third bin
  EXPECT_FALSE(m.IsCone(100, 100, 10));
  ColorLut lut;
  lut.BuildFromModel(m);
  EXPECT_EQ(lut.model_path(), path);
  for (int r = 0; r < 256; r += 5)
    for (int g = 0; g < 256; g += 7)
      for (int b = 0; b < 256; b += 3)
        ASSERT_EQ(lut.IsCone(uint8_t(r), uint8_t(g), uint8_t(b)), m.IsCone(uint8_t(r), uint8_t(g), uint8_t(b)))
            << r << " " << g << " " << b;
  lut.Build(HsiBounds());  // back to the bounds, even though they did not change
  EXPECT_TRUE(lut.model_path().empty());
  EXPECT_EQ(lut.IsCone(250, 100, 40), InBounds(HsiBounds(), 250, 100, 40));
  std::remove(path.c_str());
}

TEST(ColourModel, TypoInAKeyIsRefusedNamingFileAndKey) {
  const std::string path = Write("typo.yaml", ModelText("thresold"));
  const std::string err = LoadError(path);
  EXPECT_NE(err.find(path + ":4: unknown key 'thresold' (did you mean 'threshold'?)"), std::string::npos) << err;
  // Through the segmenter's config, as the nodelet and detect_cones load it.
  SegmenterConfig c;
  c.colour_model = path;
  try {
    Segmenter seg(c);
    ADD_FAILURE() << "a misspelt model loaded";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("colour_model: " + path + ":4: unknown key 'thresold'"), std::string::npos)
        << e.what();
  }
  std::remove(path.c_str());
}

TEST(ColourModel, WrongSizeIsRefused) {
  const std::string path = Write("short.yaml", ModelText("threshold", 16 * 16 * 15));
  const std::string err = LoadError(path);
  EXPECT_NE(err.find(path + ":5: llr: must hold 4096 bytes (8192 hex digits) for 16 bins per channel, has 7680"),
            std::string::npos)
      << err;
  const std::string bins = Write("bins.yaml",
                                 "format: cone_colour_model\nbins_per_channel: 20\nllr_scale: 0.1\n"
                                 "threshold: 0\nllr: \"00\"\n");
  EXPECT_NE(LoadError(bins).find(bins + ":2: bins_per_channel: must be 16, 32 or 64"), std::string::npos)
      << LoadError(bins);
  const std::string missing = Write("missing.yaml", "format: cone_colour_model\nbins_per_channel: 16\n");
  EXPECT_NE(LoadError(missing).find("llr: is missing"), std::string::npos) << LoadError(missing);
  for (const auto& p : {path, bins, missing}) std::remove(p.c_str());
}

// ---- synthetic images: an upright cone (linear width from the peak down), bands in white --------

struct Canvas {
  int w = 320, h = 320;
  std::vector<uint8_t> rgb = std::vector<uint8_t>(size_t(320) * 320 * 3, 0);
  Canvas() {
    for (size_t i = 0; i < rgb.size(); i += 3) rgb[i] = 60, rgb[i + 1] = 62, rgb[i + 2] = 70;  // dark asphalt
  }
  void Set(int x, int y, uint8_t r, uint8_t g, uint8_t b) {
    uint8_t* p = &rgb[(size_t(y) * w + x) * 3];
    p[0] = r, p[1] = g, p[2] = b;
  }
  // A cone from (cx, top) to the base row, 4 px wide at the top; rows for which white(y) holds are
  // a band's.
  void Cone(int cx, int top, int base, int base_w, const std::function<bool(double)>& white) {
    for (int y = top; y <= base; ++y) {
      const double f = double(y - top) / (base - top);
      const double half = 2.0 + f * (base_w / 2.0 - 2.0);
      for (int x = int(cx - half); x <= int(cx + half); ++x)
        white(f) ? Set(x, y, 235, 235, 230) : Set(x, y, 250, 95, 20);
    }
  }
  ImageView View() const { return {rgb.data(), w, h, w * 3, "rgb8"}; }
};

// The photos' settings (config/photos.yaml): no calibrated camera, a blob's outline may be off.
SegmenterConfig PhotoConfig() {
  SegmenterConfig c;
  c.border_px = 0, c.min_solidity = 0.6, c.min_axis_ratio = 1.0, c.max_axis_ratio = 12.0;
  c.max_tilt_deg = 60.0, c.merge_lateral_frac = 0.3, c.merge_gap_frac = 0.6, c.merge_band_gap_frac = 1.5;
  c.reject_bad_outline = false;
  return c;
}

void ExpectOneConeSpanning(const SegmentationResult& r, int top, int base) {
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_EQ(r.cones.size(), 1u);
  const Blob& b = r.cones[0].blob;
  EXPECT_GE(b.fragments, 2);
  EXPECT_LE(std::abs(b.bbox_y - top), 1);
  EXPECT_LE(std::abs(b.bbox_y + b.bbox_h - 1 - base), 1);
  EXPECT_LT(r.cones[0].peak_px.y(), r.cones[0].base_px.y());
}

TEST(StripedCone, OneWideWhiteBandGivesOneConeSpanningIt) {
  Canvas img;
  // A sleeve over 35-75% of the height: taller than half the orange tip above it.
  img.Cone(160, 40, 280, 120, [](double f) { return f > 0.35 && f < 0.75; });
  Segmenter seg(PhotoConfig());
  ExpectOneConeSpanning(seg.Process(img.View(), CameraModel()), 40, 280);
  // Without band merging (the thesis's collar gap only) the sleeve splits it.
  SegmenterConfig c = PhotoConfig();
  c.merge_band_gap_frac = 0.0;
  seg.SetConfig(c);
  const SegmentationResult split = seg.Process(img.View(), CameraModel());
  EXPECT_NE(split.cones.size() == 1 && split.cones[0].blob.bbox_h > 230, true);
}

TEST(StripedCone, TwoNarrowBandsGiveOneConeSpanningThem) {
  Canvas img;
  img.Cone(150, 50, 250, 90, [](double f) { return (f > 0.3 && f < 0.42) || (f > 0.6 && f < 0.72); });
  Segmenter seg(PhotoConfig());
  ExpectOneConeSpanning(seg.Process(img.View(), CameraModel()), 50, 250);
}

TEST(StripedCone, DarkGapDoesNotJoinAFarConeAbove) {
  Canvas img;
  img.Cone(160, 150, 290, 100, [](double f) { return f > 0.35 && f < 0.7; });
  img.Cone(160, 40, 95, 30, [](double) { return false; });  // a far cone, asphalt between
  Segmenter seg(PhotoConfig());
  const SegmentationResult r = seg.Process(img.View(), CameraModel());
  ASSERT_EQ(r.cones.size(), 2u);
  for (const ConeDetection& d : r.cones) EXPECT_TRUE(d.blob.bbox_y == 40 || d.blob.bbox_y == 150) << d.blob.bbox_y;
}

// ---- the silhouette check -----------------------------------------------------------------------

TEST(ConeShape, RectangleAndLetteredSignAreRejected) {
  Canvas rect;
  for (int y = 60; y < 200; ++y)
    for (int x = 120; x < 200; ++x) rect.Set(x, y, 250, 95, 20);
  Segmenter seg(PhotoConfig());
  SegmentationResult r = seg.Process(rect.View(), CameraModel());
  ASSERT_TRUE(r.ok);
  EXPECT_TRUE(r.cones.empty());
  ASSERT_EQ(r.rejected.size(), 1u);
  EXPECT_EQ(r.rejected[0].failed_gates, uint32_t(kGateShape));
  EXPECT_EQ(SegmentationGateNames(kGateShape), std::vector<std::string>{"shape"});

  // A sign: an orange panel narrowing upward (a warning triangle's outline would pass the taper),
  // with white letters cut out of it.
  Canvas sign;
  sign.Cone(160, 40, 280, 200, [](double) { return false; });
  for (int row : {150, 200, 245})
    for (int letter = 0; letter < 5; ++letter)
      for (int y = row; y < row + 22; ++y)
        for (int x = 112 + letter * 20; x < 112 + letter * 20 + 12; ++x)
          if (x - (112 + letter * 20) < 3 || y - row < 3 || y - row > 18) sign.Set(x, y, 240, 240, 240);
  r = seg.Process(sign.View(), CameraModel());
  ASSERT_TRUE(r.ok);
  EXPECT_TRUE(r.cones.empty());
  uint32_t gates = 0;
  for (const ConeDetection& d : r.rejected) gates |= d.failed_gates;
  EXPECT_TRUE(gates & kGateShape) << gates;

  // The same cone without letters passes.
  Canvas cone;
  cone.Cone(160, 40, 280, 200, [](double) { return false; });
  EXPECT_EQ(seg.Process(cone.View(), CameraModel()).cones.size(), 1u);
}

TEST(ConeShape, ChecksTaperEdgesAndHoles) {
  std::vector<cone_tracker::Run> cone, rect, inverted;
  for (int y = 0; y < 60; ++y) {
    cone.push_back({y, 50 - y / 2, 50 + y / 2});
    rect.push_back({y, 30, 70});
    inverted.push_back({y, 20 + y / 2, 80 - y / 2});
  }
  const ConeShapeConfig c;
  EXPECT_TRUE(CheckConeShape(cone, {50, 0}, {50, 59}, c).ok);
  const ConeShapeCheck r = CheckConeShape(rect, {50, 0}, {50, 59}, c);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.why, "width does not taper to the peak");
  EXPECT_FALSE(CheckConeShape(inverted, {50, 59}, {50, 0}, c).ok);  // peak below base
  std::vector<cone_tracker::Run> holed;
  for (const cone_tracker::Run& run : cone)
    if (run.y % 4 == 1 && run.x1 - run.x0 > 10)
      holed.push_back({run.y, run.x0, 47}), holed.push_back({run.y, 53, run.x1});
    else
      holed.push_back(run);
  EXPECT_TRUE(CheckConeShape(holed, {50, 0}, {50, 59}, c).ok);  // a few small holes pass
  ConeShapeConfig off;
  off.enabled = false;
  EXPECT_TRUE(CheckConeShape(rect, {50, 0}, {50, 59}, off).ok);
}

}  // namespace
}  // namespace cone_tracker
