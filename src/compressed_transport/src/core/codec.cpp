#include "compressed_transport/core/codec.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace compressed_transport {
namespace {

std::string Trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") + 1 - b);
}

bool StartsWith(const std::string& s, const std::string& p) { return s.compare(0, p.size(), p) == 0; }

// Bits per channel and channel count of the sensor_msgs encodings this codec carries; false if unknown.
bool Describe(const std::string& enc, int* bits, int* channels, bool* color) {
  *color = false;
  if (enc == "rgb8" || enc == "bgr8")
    *bits = 8, *channels = 3, *color = true;
  else if (enc == "rgba8" || enc == "bgra8")
    *bits = 8, *channels = 4, *color = true;
  else if (enc == "rgb16" || enc == "bgr16")
    *bits = 16, *channels = 3, *color = true;
  else if (enc == "rgba16" || enc == "bgra16")
    *bits = 16, *channels = 4, *color = true;
  else if (enc == "mono8" || enc == "8UC1" || (StartsWith(enc, "bayer_") && enc.back() == '8'))
    *bits = 8, *channels = 1;
  else if (enc == "mono16" || enc == "16UC1" ||
           (StartsWith(enc, "bayer_") && enc.size() > 2 && enc.compare(enc.size() - 2, 2, "16") == 0))
    *bits = 16, *channels = 1;
  else
    return false;
  return true;
}

// The pixel layout handed to OpenCV (BGR order for colour), as upstream names it in the format string.
std::string TargetEncoding(int bits, int channels, bool color, Codec codec) {
  if (!color) return "";
  if (codec == Codec::kJpeg) return "bgr8";
  if (channels == 4) return bits == 8 ? "bgra8" : "bgra16";
  return bits == 8 ? "bgr8" : "bgr16";
}

}  // namespace

bool ParseCodec(const std::string& name, Codec* codec) {
  if (name == "jpeg")
    *codec = Codec::kJpeg;
  else if (name == "png")
    *codec = Codec::kPng;
  else
    return false;
  return true;
}

std::string FormatString(const std::string& encoding, Codec codec, std::string* error) {
  int bits = 0, channels = 0;
  bool color = false;
  if (!Describe(encoding, &bits, &channels, &color)) {
    *error = "encoding '" + encoding + "' is not supported by the compressed transport";
    return "";
  }
  if (codec == Codec::kJpeg && bits != 8) {
    *error = "JPEG needs 8 bits per channel, encoding '" + encoding + "' has 16 (use format png)";
    return "";
  }
  return encoding + (codec == Codec::kJpeg ? "; jpeg compressed " : "; png compressed ") +
         TargetEncoding(bits, channels, color, codec);
}

bool Encode(const cv::Mat& image, const std::string& encoding, const EncodeConfig& config, EncodedImage* out,
            std::string* error) {
  out->format = FormatString(encoding, config.codec, error);
  if (out->format.empty()) return false;
  int bits = 0, channels = 0;
  bool color = false;
  Describe(encoding, &bits, &channels, &color);
  if (image.channels() != channels || (bits == 8) != (image.depth() == CV_8U)) {
    *error = "image of encoding '" + encoding + "' has " + std::to_string(image.channels()) +
             " channel(s) of the wrong depth";
    return false;
  }
  // OpenCV writes BGR order. The converted copy is our own: `image` may be a publisher's shared frame.
  cv::Mat converted;
  const bool rgb_order = StartsWith(encoding, "rgb");
  if (config.codec == Codec::kJpeg && channels == 4) {
    cv::cvtColor(image, converted, rgb_order ? cv::COLOR_RGBA2BGR : cv::COLOR_BGRA2BGR);
  } else if (rgb_order) {
    cv::cvtColor(image, converted, channels == 4 ? cv::COLOR_RGBA2BGRA : cv::COLOR_RGB2BGR);
  }
  const cv::Mat& pixels = converted.empty() ? image : converted;
  std::vector<int> params;
  if (config.codec == Codec::kJpeg) {
    params = {cv::IMWRITE_JPEG_QUALITY,      config.jpeg_quality,          cv::IMWRITE_JPEG_OPTIMIZE,
              config.jpeg_optimize ? 1 : 0,  cv::IMWRITE_JPEG_PROGRESSIVE, config.jpeg_progressive ? 1 : 0,
              cv::IMWRITE_JPEG_RST_INTERVAL, config.jpeg_restart_interval};
  } else {
    params = {cv::IMWRITE_PNG_COMPRESSION, config.png_level};
  }
  try {
    if (!cv::imencode(config.codec == Codec::kJpeg ? ".jpg" : ".png", pixels, out->data, params)) {
      *error = "OpenCV could not encode the image";
      return false;
    }
  } catch (const cv::Exception& e) {
    *error = std::string("OpenCV could not encode the image: ") + e.what();
    return false;
  }
  return true;
}

bool Decode(const std::string& format, const std::vector<uint8_t>& data, DecodedImage* out, std::string* error) {
  if (data.empty()) {
    *error = "empty payload";
    return false;
  }
  // "rgb8; jpeg compressed bgr8": the original encoding before ';'. Old style "jpeg": none given.
  const size_t semicolon = format.find(';');
  std::string encoding = semicolon == std::string::npos ? "" : Trim(format.substr(0, semicolon));
  cv::Mat decoded;
  try {
    decoded = cv::imdecode(cv::Mat(1, static_cast<int>(data.size()), CV_8UC1, const_cast<uint8_t*>(data.data())),
                           cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    decoded = cv::Mat();
  }
  if (decoded.empty()) {
    *error =
        "payload of " + std::to_string(data.size()) + " bytes is not a decodable JPEG or PNG (format '" + format + "')";
    return false;
  }
  if (encoding.empty())
    encoding = decoded.channels() == 1   ? (decoded.depth() == CV_8U ? "mono8" : "mono16")
               : decoded.channels() == 4 ? "bgra8"
                                         : "bgr8";
  int bits = 0, channels = 0;
  bool color = false;
  if (!Describe(encoding, &bits, &channels, &color)) {
    *error = "format '" + format + "' names encoding '" + encoding + "', which is not supported";
    return false;
  }
  if (decoded.depth() != (bits == 8 ? CV_8U : CV_16U)) decoded.convertTo(decoded, bits == 8 ? CV_8U : CV_16U);
  const bool rgb_order = StartsWith(encoding, "rgb");
  if (channels == 1) {
    if (decoded.channels() != 1) cv::cvtColor(decoded, decoded, cv::COLOR_BGR2GRAY);
  } else if (decoded.channels() == 1) {
    *error = "format '" + format + "' says " + std::to_string(channels) + " channels, the payload has 1";
    return false;
  } else if (channels == 3) {
    if (decoded.channels() == 4) cv::cvtColor(decoded, decoded, cv::COLOR_BGRA2BGR);
    if (rgb_order) cv::cvtColor(decoded, decoded, cv::COLOR_BGR2RGB);
  } else {  // 4 channels: JPEG carried 3
    if (decoded.channels() == 3)
      cv::cvtColor(decoded, decoded, rgb_order ? cv::COLOR_BGR2RGBA : cv::COLOR_BGR2BGRA);
    else if (rgb_order)
      cv::cvtColor(decoded, decoded, cv::COLOR_BGRA2RGBA);
  }
  out->image = decoded;
  out->encoding = encoding;
  return true;
}

}  // namespace compressed_transport
