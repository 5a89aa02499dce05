#include "aravis_camera/core/pixel_format.h"

#include <array>

namespace aravis_camera {

namespace {
struct FormatEntry {
  const char* genicam;
  const char* encoding;  // values of sensor_msgs::image_encodings, spelled out to keep this file ROS-free
  int bytes_per_pixel;
};
// Bayer names: GenICam names the colour of the first two pixels of the first
// row, as ROS does (BayerRG8 starts R G, like bayer_rggb8).
constexpr std::array<FormatEntry, 7> kFormats{{
    {"RGB8", "rgb8", 3},
    {"BGR8", "bgr8", 3},
    {"BayerRG8", "bayer_rggb8", 1},
    {"BayerGR8", "bayer_grbg8", 1},
    {"BayerGB8", "bayer_gbrg8", 1},
    {"BayerBG8", "bayer_bggr8", 1},
    {"Mono8", "mono8", 1},
}};
}  // namespace

std::string EncodingForPixelFormat(const std::string& pixel_format) {
  for (const auto& f : kFormats) {
    if (pixel_format == f.genicam) return f.encoding;
  }
  return "";
}

int BytesPerPixel(const std::string& pixel_format) {
  for (const auto& f : kFormats) {
    if (pixel_format == f.genicam) return f.bytes_per_pixel;
  }
  return 0;
}

std::string SupportedPixelFormats() {
  std::string s;
  for (const auto& f : kFormats) s += (s.empty() ? "" : ", ") + std::string(f.genicam);
  return s;
}

}  // namespace aravis_camera
