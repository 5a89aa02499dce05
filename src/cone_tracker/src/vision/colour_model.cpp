#include "cone_tracker/vision/colour_model.h"

#include <cmath>

#include "rig_model/strict_yaml.h"

namespace cone_tracker {

namespace {
int HexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}
}  // namespace

bool ColourModel::IsCone(uint8_t r, uint8_t g, uint8_t b) const {
  const int shift = bins_per_channel == 16 ? 4 : bins_per_channel == 32 ? 3 : 2;
  const size_t i = (size_t(r >> shift) * bins_per_channel + size_t(g >> shift)) * bins_per_channel + (b >> shift);
  return llr[i] * llr_scale >= threshold;
}

ColourModel LoadColourModel(const std::string& path) {
  const rig_model::StrictReader reader(path);
  const YAML::Node root = rig_model::LoadYamlFile(path);
  if (!root.IsMap())
    throw rig_model::FileError(path +
                               ": not a colour model (a YAML mapping with 'format: "
                               "cone_colour_model'), written by calibrate_cone_colour");
  reader.CheckKeys(root, {"format", "bins_per_channel", "llr_scale", "threshold", "llr"}, "");
  ColourModel m;
  m.path = path;
  for (const char* key : {"format", "llr"})
    if (!root[key]) reader.Fail(root, key, "is missing");
  const std::string format = reader.String(root, "", "format", "");
  if (format != "cone_colour_model")
    reader.Fail(root["format"], "format", "must be 'cone_colour_model', not '" + format + "'");
  const double bins = reader.RequiredNumber(root, "", "bins_per_channel");
  if (bins != 16 && bins != 32 && bins != 64)
    reader.Fail(root["bins_per_channel"], "bins_per_channel", "must be 16, 32 or 64");
  m.bins_per_channel = int(bins);
  m.llr_scale = reader.RequiredNumber(root, "", "llr_scale");
  if (!(m.llr_scale > 0.0)) reader.Fail(root["llr_scale"], "llr_scale", "must be > 0");
  m.threshold = reader.RequiredNumber(root, "", "threshold");
  const std::string hex = reader.String(root, "", "llr", "");
  const size_t n = size_t(m.bins_per_channel) * m.bins_per_channel * m.bins_per_channel;
  if (hex.size() != 2 * n)
    reader.Fail(root["llr"], "llr",
                "must hold " + std::to_string(n) + " bytes (" + std::to_string(2 * n) + " hex digits) for " +
                    std::to_string(m.bins_per_channel) + " bins per channel, has " + std::to_string(hex.size()) +
                    " hex digits");
  m.llr.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const int hi = HexDigit(hex[2 * i]), lo = HexDigit(hex[2 * i + 1]);
    if (hi < 0 || lo < 0)
      reader.Fail(root["llr"], "llr", "is not hex at digit " + std::to_string(2 * i + (hi < 0 ? 0 : 1)));
    m.llr[i] = int8_t(uint8_t(hi * 16 + lo));
  }
  return m;
}

}  // namespace cone_tracker
