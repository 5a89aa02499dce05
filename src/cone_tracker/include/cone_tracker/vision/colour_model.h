// A colour table learned from labelled pixels (3.1.5.1's RGB table filled from data instead of HSI
// bounds): a bins^3 table over RGB of the log-likelihood ratio log(P(rgb | cone) / P(rgb | background))
// in steps of llr_scale, and the threshold at or above which a pixel is cone. Written by
// scripts/calibrate_cone_colour; read strictly. ROS-free.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace cone_tracker {

struct ColourModel {
  std::string path;  // the file it came from
  int bins_per_channel = 32;
  double llr_scale = 0.125;
  double threshold = 0.0;
  std::vector<int8_t> llr;  // r-major: ((r_bin * bins) + g_bin) * bins + b_bin

  // Whether the bin of this 8-bit colour is cone.
  bool IsCone(uint8_t r, uint8_t g, uint8_t b) const;
};

// Reads a model file. Throws rig_model::FileError naming the file, line and field on an unknown or
// misspelt key, a missing one, a wrong format name, a bin count other than 16, 32 or 64, or a table
// of the wrong size or not in hex.
ColourModel LoadColourModel(const std::string& path);

}  // namespace cone_tracker
