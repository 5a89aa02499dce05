#include "ar_overlay/core/composite.h"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace ar_overlay {
namespace {

// c + keep/255 of `under`, saturated (rounding can reach 256).
inline uint8_t Add(unsigned c, unsigned under, unsigned keep) {
  const unsigned v = c + (under * keep + 127) / 255;
  return static_cast<uint8_t>(v > 255 ? 255 : v);
}

}  // namespace

void ToColor(const cv::Mat& image, const std::string& encoding, cv::Mat& out, std::string& out_encoding) {
  out_encoding = "bgr8";
  if (encoding == "rgb8" || encoding == "bgr8") {
    out_encoding = encoding;
    image.copyTo(out);
  } else if (encoding == "rgba8") {
    out_encoding = "rgb8";
    cv::cvtColor(image, out, cv::COLOR_RGBA2RGB);
  } else if (encoding == "bgra8") {
    cv::cvtColor(image, out, cv::COLOR_BGRA2BGR);
  } else if (encoding == "mono8") {
    cv::cvtColor(image, out, cv::COLOR_GRAY2BGR);
  } else if (encoding == "bayer_rggb8") {  // OpenCV names Bayer patterns by the second row
    cv::cvtColor(image, out, cv::COLOR_BayerBG2BGR);
  } else if (encoding == "bayer_bggr8") {
    cv::cvtColor(image, out, cv::COLOR_BayerRG2BGR);
  } else if (encoding == "bayer_gbrg8") {
    cv::cvtColor(image, out, cv::COLOR_BayerGR2BGR);
  } else if (encoding == "bayer_grbg8") {
    cv::cvtColor(image, out, cv::COLOR_BayerGB2BGR);
  } else {
    throw std::invalid_argument("ar_overlay: unsupported image encoding '" + encoding +
                                "' (rgb8, bgr8, rgba8, bgra8, mono8, bayer_*8)");
  }
  if (out.type() != CV_8UC3) throw std::invalid_argument("ar_overlay: image data does not match '" + encoding + "'");
}

void CompositeInPlace(const cv::Mat& overlay_rgba, const std::string& encoding, cv::Mat& image) {
  if (overlay_rgba.type() != CV_8UC4 || image.type() != CV_8UC3 || overlay_rgba.size() != image.size())
    throw std::invalid_argument("ar_overlay: composite needs an RGBA overlay the size of the 8-bit colour image");
  const bool bgr = encoding == "bgr8";
  // Rows in parallel (OpenCV's pool): the overlay's region can be most of the frame.
  cv::parallel_for_(cv::Range(0, image.rows), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      const uint8_t* o = overlay_rgba.ptr<uint8_t>(v);
      uint8_t* p = image.ptr<uint8_t>(v);
      for (int u = 0; u < image.cols; ++u, o += 4, p += 3) {
        const unsigned a = o[3];
        if (a == 0) continue;  // most of the frame: leave the camera's pixel alone
        const unsigned keep = 255 - a;
        // The overlay is premultiplied (renderer.cpp): out = c + (1 - a) image.
        const uint8_t r = o[0], g = o[1], b = o[2];
        p[0] = Add((bgr ? b : r), p[0], keep);
        p[1] = Add(g, p[1], keep);
        p[2] = Add((bgr ? r : b), p[2], keep);
      }
    }
  });
}

}  // namespace ar_overlay
