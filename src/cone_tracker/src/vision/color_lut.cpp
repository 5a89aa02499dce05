#include "cone_tracker/vision/color_lut.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cone_tracker {

namespace {
constexpr double kTwoPi = 2.0 * M_PI;
constexpr double kDegToRad = M_PI / 180.0;
}  // namespace

std::string HsiBounds::Validate() const {
  auto finite_in = [](double x, double lo, double hi) { return std::isfinite(x) && x >= lo && x <= hi; };
  if (!finite_in(hue_min_deg, 0.0, 360.0)) return "hue_min_deg must be in [0, 360]";
  if (!finite_in(hue_max_deg, 0.0, 360.0)) return "hue_max_deg must be in [0, 360]";
  if (!finite_in(sat_min, 0.0, 1.0)) return "sat_min must be in [0, 1]";
  if (!finite_in(sat_max, 0.0, 1.0) || sat_max < sat_min) return "sat_max must be in [sat_min, 1]";
  if (!finite_in(val_min, 0.0, 1.0)) return "val_min must be in [0, 1]";
  if (!finite_in(val_max, 0.0, 1.0) || val_max < val_min) return "val_max must be in [val_min, 1]";
  return "";
}

bool HsiBounds::operator==(const HsiBounds& o) const {
  return hue_min_deg == o.hue_min_deg && hue_max_deg == o.hue_max_deg && sat_min == o.sat_min && sat_max == o.sat_max &&
         val_min == o.val_min && val_max == o.val_max;
}

void RgbToHsv(uint8_t r8, uint8_t g8, uint8_t b8, double* h_rad, double* s, double* v) {
  const double r = r8 / 255.0, g = g8 / 255.0, b = b8 / 255.0;
  const double mx = std::max({r, g, b}), mn = std::min({r, g, b});
  const double d = mx - mn;
  double h = 0.0;  // (3.19)
  if (d > 0.0) {
    if (mx == r)
      h = M_PI / 3.0 * (g - b) / d;
    else if (mx == g)
      h = M_PI / 3.0 * (b - r) / d + 2.0 * M_PI / 3.0;
    else
      h = M_PI / 3.0 * (r - g) / d + 4.0 * M_PI / 3.0;
    if (h < 0.0) h += kTwoPi;
  }
  *h_rad = h;
  *s = mx > 0.0 ? d / mx : 0.0;  // (3.20)
  *v = mx;                       // (3.21)
}

bool InBounds(const HsiBounds& k, uint8_t r, uint8_t g, uint8_t b) {
  double h, s, v;
  RgbToHsv(r, g, b, &h, &s, &v);
  const double lo = k.hue_min_deg * kDegToRad, hi = k.hue_max_deg * kDegToRad;
  const bool hue_ok = lo <= hi ? (h >= lo && h <= hi) : (h >= lo || h <= hi);
  return hue_ok && s >= k.sat_min && s <= k.sat_max && v >= k.val_min && v <= k.val_max;  // (3.22)
}

namespace {
const HsiBounds& Validated(const HsiBounds& bounds) {
  const std::string error = bounds.Validate();
  if (!error.empty()) throw std::invalid_argument("HsiBounds: " + error);
  return bounds;
}
}  // namespace

ColorLut::ColorLut() : ColorLut(HsiBounds()) {}

ColorLut::ColorLut(const HsiBounds& bounds) : bounds_(Validated(bounds)), bits_(size_t(1) << 18, 0) { Fill(); }

void ColorLut::Build(const HsiBounds& bounds) {
  if (Validated(bounds) == bounds_ && model_path_.empty()) return;
  bounds_ = bounds;
  model_path_.clear();
  Fill();
}

void ColorLut::Fill() {
  std::fill(bits_.begin(), bits_.end(), 0);
  for (uint32_t i = 0; i < (1u << 24); ++i) {
    if (InBounds(bounds_, uint8_t(i >> 16), uint8_t(i >> 8), uint8_t(i))) bits_[i >> 6] |= uint64_t(1) << (i & 63);
  }
}

void ColorLut::BuildFromModel(const ColourModel& model) {
  std::fill(bits_.begin(), bits_.end(), 0);
  for (uint32_t i = 0; i < (1u << 24); i += 8) {  // a bin spans at least 4 blue values: test in pairs of 4
    const uint8_t r = uint8_t(i >> 16), g = uint8_t(i >> 8), b = uint8_t(i);
    uint64_t byte = 0;
    if (model.IsCone(r, g, b)) byte |= 0x0f;
    if (model.IsCone(r, g, uint8_t(b + 4))) byte |= 0xf0;
    bits_[i >> 6] |= byte << (i & 63);
  }
  model_path_ = model.path;
}

}  // namespace cone_tracker
