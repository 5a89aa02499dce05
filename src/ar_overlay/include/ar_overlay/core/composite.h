// Puts an RGBA overlay over a camera image: out = (1 - a) image + a overlay.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace ar_overlay {

// The colour image to draw on, from a sensor_msgs/Image encoding: rgb8 and
// bgr8 pass through (copied), rgba8/bgra8 drop alpha, mono8 and bayer_*8 are
// converted to bgr8, into `out` (whose buffer is reused when it already has the
// size and CV_8UC3, so a caller can hand in a message's memory). Sets
// `out_encoding`; throws std::invalid_argument naming an unsupported encoding.
void ToColor(const cv::Mat& image, const std::string& encoding, cv::Mat& out, std::string& out_encoding);

// Blends `overlay_rgba` (CV_8UC4, R G B A) into `image` (CV_8UC3 in
// `encoding`, rgb8 or bgr8) in place. Sizes must match (std::invalid_argument).
void CompositeInPlace(const cv::Mat& overlay_rgba, const std::string& encoding, cv::Mat& image);

}  // namespace ar_overlay
