#include "aravis_camera/node/ros_config.h"

#include <stdexcept>

#include "rig_model/ros/params.h"

namespace aravis_camera {
namespace {

// Absent: the struct's default stays; a wrong type throws naming the parameter (roscpp's param()
// kept the default silently). What dynamic_reconfigure writes back reads again as it is.
template <typename T>
void Get(const ros::NodeHandle& pnh, const std::string& name, T* value) {
  rig_model::GetParam(pnh, name, value);
}

}  // namespace

CameraConfig LoadConfig(const ros::NodeHandle& pnh) {
  CameraConfig c;
  Get(pnh, "camera_name", &c.camera_name);
  Get(pnh, "enable_fake_interface", &c.enable_fake_interface);
  Get(pnh, "pixel_format", &c.pixel_format);
  Get(pnh, "width", &c.width_px);
  Get(pnh, "height", &c.height_px);
  Get(pnh, "offset_x", &c.offset_x_px);
  Get(pnh, "offset_y", &c.offset_y_px);
  Get(pnh, "frame_rate", &c.frame_rate_hz);
  Get(pnh, "exposure_auto", &c.exposure_auto);
  Get(pnh, "exposure", &c.exposure_us);
  Get(pnh, "gain", &c.gain_db);
  Get(pnh, "packet_size", &c.packet_size_bytes);
  Get(pnh, "inter_packet_delay", &c.inter_packet_delay_ns);
  Get(pnh, "n_buffers", &c.n_buffers);
  Get(pnh, "publish_incomplete", &c.publish_incomplete);
  Get(pnh, "reconnect_period", &c.reconnect_period_s);
  Get(pnh, "frame_timeout", &c.frame_timeout_s);
  Get(pnh, "stamp_offset", &c.stamp_offset_s);
  Get(pnh, "frame_id", &c.frame_id);
  std::string stamp = "device";
  Get(pnh, "stamp_source", &stamp);
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
