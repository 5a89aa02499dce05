// Colour classification (3.1.5.1): the six HSI bounds (3.22) compiled
// into a table over all 2^24 RGB values, one bit each (2 MiB, so it stays in
// cache better than a byte table), so classifying a pixel is one lookup.
// ROS-free.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "cone_tracker/vision/colour_model.h"

namespace cone_tracker {

// Bounds of (3.22). Hue in degrees on [0, 360], as the parameters give it (the
// table converts to the radians of (3.19)); hue_min_deg > hue_max_deg means the
// band wraps through red (0). Saturation and value on [0, 1].
struct HsiBounds {
  double hue_min_deg = 0.0;                    // orange under sun and shade on the rig_sim cones
  double hue_max_deg = 0.70 / (M_PI / 180.0);  // 0.70 rad, ~40.1 deg
  double sat_min = 0.55;
  double sat_max = 1.0;
  double val_min = 0.20;
  double val_max = 1.0;

  // Empty when valid, else a message naming the bad field.
  std::string Validate() const;
  bool operator==(const HsiBounds& o) const;
  bool operator!=(const HsiBounds& o) const { return !(*this == o); }
};

// HSV of one 8-bit RGB pixel by (3.19) (3.20) (3.21): hue in [0, 2*pi), s and v in [0, 1].
void RgbToHsv(uint8_t r, uint8_t g, uint8_t b, double* h_rad, double* s, double* v);

// (3.22) evaluated directly, without the table (the table's reference).
bool InBounds(const HsiBounds& bounds, uint8_t r, uint8_t g, uint8_t b);

class ColorLut {
 public:
  ColorLut();  // built from the default bounds
  // Built from these bounds; throws std::invalid_argument like Build().
  explicit ColorLut(const HsiBounds& bounds);
  // Rebuilds the table (~100 ms); a no-op when the bounds are unchanged.
  // Throws std::invalid_argument with Validate()'s message on bad bounds.
  void Build(const HsiBounds& bounds);
  const HsiBounds& bounds() const { return bounds_; }
  // Fills the table from a learned model instead (~50 ms); a later Build() refills from bounds.
  void BuildFromModel(const ColourModel& model);
  // The model's file when the table came from one, else "".
  const std::string& model_path() const { return model_path_; }

  bool IsCone(uint8_t r, uint8_t g, uint8_t b) const {
    const uint32_t i = (uint32_t(r) << 16) | (uint32_t(g) << 8) | b;
    return (bits_[i >> 6] >> (i & 63)) & 1u;
  }

 private:
  void Fill();
  HsiBounds bounds_;
  std::string model_path_;
  std::vector<uint64_t> bits_;
};

}  // namespace cone_tracker
