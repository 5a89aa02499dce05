#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "cone_tracker/vision/color_lut.h"

namespace cone_tracker {

TEST(ColorLut, HsvKnownValues) {
  double h, s, v;
  RgbToHsv(255, 128, 0, &h, &s, &v);  // orange: 30 deg
  EXPECT_NEAR(h, M_PI / 3.0 * 128.0 / 255.0, 1e-12);
  EXPECT_DOUBLE_EQ(s, 1.0);
  EXPECT_DOUBLE_EQ(v, 1.0);
  RgbToHsv(0, 0, 255, &h, &s, &v);  // blue: 240 deg
  EXPECT_NEAR(h, 4.0 * M_PI / 3.0, 1e-12);
  RgbToHsv(255, 0, 64, &h, &s, &v);  // magenta-red wraps below 2 pi
  EXPECT_GT(h, 5.0);
  EXPECT_LT(h, 2.0 * M_PI);
  RgbToHsv(0, 0, 0, &h, &s, &v);  // black: no NaN
  EXPECT_EQ(h, 0.0);
  EXPECT_EQ(s, 0.0);
}

TEST(ColorLut, TableMatchesDirectClassificationAndRebuilds) {
  ColorLut lut;
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> byte(0, 255);
  HsiBounds wrap;
  wrap.hue_min_deg = 315.0, wrap.hue_max_deg = 23.0;  // through red
  for (const HsiBounds& b : {HsiBounds(), wrap}) {
    lut.Build(b);
    int positives = 0;
    for (int i = 0; i < 200000; ++i) {
      const uint8_t r = byte(rng), g = byte(rng), bl = byte(rng);
      ASSERT_EQ(lut.IsCone(r, g, bl), InBounds(b, r, g, bl)) << int(r) << " " << int(g) << " " << int(bl);
      positives += lut.IsCone(r, g, bl);
    }
    EXPECT_GT(positives, 1000);
  }
  EXPECT_TRUE(lut.IsCone(255, 10, 40));  // the wrapped band holds red-magenta
  lut.Build(HsiBounds());
  EXPECT_FALSE(lut.IsCone(255, 10, 40));
  EXPECT_TRUE(lut.IsCone(230, 80, 10));
}

TEST(ColorLut, BadBoundsThrowNamingTheField) {
  ColorLut lut;
  HsiBounds b;
  b.sat_max = 0.1;  // below sat_min
  try {
    lut.Build(b);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sat_max"), std::string::npos);
  }
  b = HsiBounds();
  b.val_min = NAN;
  EXPECT_THROW(lut.Build(b), std::invalid_argument);
  EXPECT_TRUE(lut.IsCone(230, 80, 10));  // unchanged after a refused build
}

}  // namespace cone_tracker
