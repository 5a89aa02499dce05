// GenICam pixel format names <-> sensor_msgs/Image encodings.
#pragma once

#include <string>

namespace aravis_camera {

// The ROS encoding (sensor_msgs/image_encodings.h) for a GenICam PixelFormat
// name, or "" if the driver does not support it.
std::string EncodingForPixelFormat(const std::string& pixel_format);

// Bytes per pixel of a supported format (all are 8-bit per channel).
int BytesPerPixel(const std::string& pixel_format);

// "RGB8, BGR8, BayerRG8, ..." for messages.
std::string SupportedPixelFormats();

}  // namespace aravis_camera
