#include "aravis_camera/node/ros_config.h"

#include <stdexcept>

namespace aravis_camera {

CameraConfig LoadConfig(const ros::NodeHandle& pnh) {
  CameraConfig c;
  pnh.param("camera_name", c.camera_name, c.camera_name);
  pnh.param("enable_fake_interface", c.enable_fake_interface, c.enable_fake_interface);
  pnh.param("pixel_format", c.pixel_format, c.pixel_format);
  pnh.param("width", c.width_px, c.width_px);
  pnh.param("height", c.height_px, c.height_px);
  pnh.param("offset_x", c.offset_x_px, c.offset_x_px);
  pnh.param("offset_y", c.offset_y_px, c.offset_y_px);
  pnh.param("frame_rate", c.frame_rate_hz, c.frame_rate_hz);
  pnh.param("exposure_auto", c.exposure_auto, c.exposure_auto);
  pnh.param("exposure", c.exposure_us, c.exposure_us);
  pnh.param("gain", c.gain_db, c.gain_db);
  pnh.param("packet_size", c.packet_size_bytes, c.packet_size_bytes);
  pnh.param("inter_packet_delay", c.inter_packet_delay_ns, c.inter_packet_delay_ns);
  pnh.param("n_buffers", c.n_buffers, c.n_buffers);
  pnh.param("publish_incomplete", c.publish_incomplete, c.publish_incomplete);
  pnh.param("reconnect_period", c.reconnect_period_s, c.reconnect_period_s);
  pnh.param("frame_timeout", c.frame_timeout_s, c.frame_timeout_s);
  pnh.param("stamp_offset", c.stamp_offset_s, c.stamp_offset_s);
  pnh.param("frame_id", c.frame_id, c.frame_id);
  std::string stamp = "device";
  pnh.param("stamp_source", stamp, stamp);
  if (stamp == "device") {
    c.stamp_source = StampSource::kDevice;
  } else if (stamp == "host") {
    c.stamp_source = StampSource::kHost;
  } else if (stamp == "completion") {
    c.stamp_source = StampSource::kCompletion;
  } else {
    throw std::invalid_argument("parameter ~stamp_source: '" + stamp + "' is not one of device, host, completion");
  }
  const std::string error = Validate(c);
  if (!error.empty()) throw std::invalid_argument(error);
  return c;
}

}  // namespace aravis_camera
