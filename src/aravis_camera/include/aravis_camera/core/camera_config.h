// Settings of the GigE Vision camera driver. One struct, units in the names;
// filled from ROS parameters by LoadConfig (ros_config.h) and validated here so
// the core never sees a NodeHandle.
#pragma once

#include <string>

namespace aravis_camera {

// What a frame's header.stamp is. The default maps the camera's own timestamp
// (latched by the camera, so free of network jitter) to the host clock; the
// host-clock choices are for cameras without usable timestamps.
// ~stamp_source's values, in the order of the names the parameter takes (device, host, completion).
enum StampSource : int {
  kDevice,      // the camera's timestamp mapped to the host clock (timestamp_mapper.h)
  kHost,        // host clock at the frame's first packet (Aravis's system timestamp)
  kCompletion,  // host clock when the last packet arrived and the frame was complete
};

struct CameraConfig {
  // Which camera: empty opens the first one found; otherwise a device id, an IP
  // address (needed on loopback, where discovery broadcasts do not reach), or a
  // serial number looked up in the discovered device list.
  std::string camera_name;
  // Also list Aravis's in-process fake camera (id "Fake_1", serial "1"):
  // for trying the driver, and for tests of discovery, without a camera.
  bool enable_fake_interface = false;
  std::string pixel_format = "BayerRG8";  // RGB8, BayerRG8/GR8/GB8/BG8, Mono8
  int width_px = 0;                       // 0: the camera's current/maximum
  int height_px = 0;
  int offset_x_px = 0;
  int offset_y_px = 0;
  double frame_rate_hz = 30.0;
  bool exposure_auto = false;
  double exposure_us = 10000.0;
  double gain_db = 0.0;
  int packet_size_bytes = 0;  // 0: negotiate the largest the path allows
  int inter_packet_delay_ns = 0;
  int n_buffers = 8;                        // stream buffers in the zero-copy pool
  bool publish_incomplete = false;          // publish frames with missing packets (counted either way)
  double reconnect_period_s = 0.5;          // between attempts to open a camera that is absent or lost
  double frame_timeout_s = 2.0;             // no frame for this long while streaming: treat the camera as lost
  int stamp_source = StampSource::kDevice;  // a StampSource
  double stamp_offset_s = 0.0;              // subtracted from every stamp: the rig's calibrated exposure-to-stamp delay
  std::string frame_id = "camera_optical";
};

// Returns an empty string if `c` is usable, otherwise a message naming the
// first bad parameter and the accepted range.
std::string Validate(const CameraConfig& c);

}  // namespace aravis_camera
