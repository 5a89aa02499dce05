#include "aravis_camera/core/camera_config.h"

#include <cmath>

#include "aravis_camera/core/pixel_format.h"

namespace aravis_camera {

namespace {
std::string Bad(const std::string& name, const std::string& why) { return "parameter ~" + name + ": " + why; }
}  // namespace

std::string Validate(const CameraConfig& c) {
  if (EncodingForPixelFormat(c.pixel_format).empty()) {
    return Bad("pixel_format", "'" + c.pixel_format + "' is not one of " + SupportedPixelFormats());
  }
  if (c.width_px < 0 || c.height_px < 0) return Bad("width/height", "must be >= 0 (0 keeps the camera's)");
  if (c.offset_x_px < 0 || c.offset_y_px < 0) return Bad("offset_x/offset_y", "must be >= 0");
  if (!(c.frame_rate_hz > 0.0 && c.frame_rate_hz <= 1000.0)) return Bad("frame_rate", "must be in (0, 1000] Hz");
  if (!(c.exposure_us > 0.0 && std::isfinite(c.exposure_us))) return Bad("exposure", "must be > 0 us");
  if (!std::isfinite(c.gain_db)) return Bad("gain", "must be finite (dB)");
  if (c.packet_size_bytes != 0 && (c.packet_size_bytes < 576 || c.packet_size_bytes > 16000)) {
    return Bad("packet_size", "must be 0 (negotiate) or in [576, 16000] bytes");
  }
  if (c.inter_packet_delay_ns < 0) return Bad("inter_packet_delay", "must be >= 0 ns");
  if (c.n_buffers < 2 || c.n_buffers > 256) return Bad("n_buffers", "must be in [2, 256]");
  if (!(c.reconnect_period_s > 0.0 && c.reconnect_period_s <= 60.0))
    return Bad("reconnect_period", "must be in (0, 60] s");
  if (!(c.frame_timeout_s > 0.0)) return Bad("frame_timeout", "must be > 0 s");
  if (!std::isfinite(c.stamp_offset_s)) return Bad("stamp_offset", "must be finite (s)");
  if (c.frame_id.empty()) return Bad("frame_id", "must not be empty");
  return "";
}

}  // namespace aravis_camera
