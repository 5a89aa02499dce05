// JPEG/PNG encoding and decoding of image buffers with OpenCV, in the message conventions of
// compressed_image_transport (ros-perception/image_transport_plugins): the CompressedImage's `format`
// is "<image encoding>; <jpeg|png> compressed <encoding of the compressed pixels>", e.g.
// "rgb8; jpeg compressed bgr8" (OpenCV compresses BGR order), or "mono8; png compressed " for one
// channel. Older publishers send just "jpeg" or "png"; Decode reads those too. No ROS header here.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace compressed_transport {

enum class Codec { kJpeg, kPng };

struct EncodeConfig {
  Codec codec = Codec::kJpeg;
  int jpeg_quality = 80;  // 1..100
  // Optimised Huffman tables: about 9 % smaller for about 2 ms more per 1024x768 frame. On, unlike
  // upstream's default, so that the 30 Hz overlay fits 2 MB/s (make bench, README).
  bool jpeg_optimize = true;
  bool jpeg_progressive = false;  // progressive JPEG
  int jpeg_restart_interval = 0;  // 0..65535, 0: no restart markers
  int png_level = 9;              // 1..9 (zlib)
};

// "jpeg" -> kJpeg, "png" -> kPng; false for anything else.
bool ParseCodec(const std::string& name, Codec* codec);

struct EncodedImage {
  std::string format;         // the CompressedImage's format string
  std::vector<uint8_t> data;  // the JPEG or PNG file
};

// The format string for an image of `encoding` compressed with `codec`; empty (and *error set) when the
// codec cannot carry the encoding (JPEG: 8 bits per channel only; PNG: 8 or 16).
std::string FormatString(const std::string& encoding, Codec codec, std::string* error);

// Encodes `image` (pixels in sensor_msgs encoding `encoding`: rgb8, bgr8, rgba8, bgra8, mono8, bayer_*8,
// and for PNG also the 16-bit ones). False with *error naming the encoding or the failure.
bool Encode(const cv::Mat& image, const std::string& encoding, const EncodeConfig& config, EncodedImage* out,
            std::string* error);

struct DecodedImage {
  cv::Mat image;         // pixels in `encoding`
  std::string encoding;  // the sensor_msgs encoding of the original image
};

// Decodes a CompressedImage payload with its format string. False with *error saying why (empty
// payload, not a JPEG/PNG, a size or channel count that contradicts the format string).
bool Decode(const std::string& format, const std::vector<uint8_t>& data, DecodedImage* out, std::string* error);

}  // namespace compressed_transport
