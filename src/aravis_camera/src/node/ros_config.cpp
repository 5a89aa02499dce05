#include "aravis_camera/node/ros_config.h"

#include <stdexcept>

#include "rig_model/ros/param_table_ros.h"

namespace aravis_camera {

const rig_model::ParamTable<NodeConfig>& Params() {
  using C = NodeConfig;
  static const rig_model::ParamTable<C> table =
      rig_model::ParamTable<C>()
          .Add("camera_name", [](C& c) -> std::string& { return c.camera.camera_name; })
          .Add("enable_fake_interface", [](C& c) -> bool& { return c.camera.enable_fake_interface; })
          .Add("pixel_format", [](C& c) -> std::string& { return c.camera.pixel_format; })
          .Add("width", [](C& c) -> int& { return c.camera.width_px; })
          .Add("height", [](C& c) -> int& { return c.camera.height_px; })
          .Add("offset_x", [](C& c) -> int& { return c.camera.offset_x_px; })
          .Add("offset_y", [](C& c) -> int& { return c.camera.offset_y_px; })
          .Add("frame_rate", [](C& c) -> double& { return c.camera.frame_rate_hz; })
          .Add("exposure_auto", [](C& c) -> bool& { return c.camera.exposure_auto; })
          .Add("exposure", [](C& c) -> double& { return c.camera.exposure_us; })
          .Add("gain", [](C& c) -> double& { return c.camera.gain_db; })
          .Add("packet_size", [](C& c) -> int& { return c.camera.packet_size_bytes; })
          .Add("inter_packet_delay", [](C& c) -> int& { return c.camera.inter_packet_delay_ns; })
          .Add("n_buffers", [](C& c) -> int& { return c.camera.n_buffers; })
          .Add("publish_incomplete", [](C& c) -> bool& { return c.camera.publish_incomplete; })
          .Add("reconnect_period", [](C& c) -> double& { return c.camera.reconnect_period_s; })
          .Add("frame_timeout", [](C& c) -> double& { return c.camera.frame_timeout_s; })
          .AddEnum("stamp_source", [](C& c) -> int& { return c.camera.stamp_source; }, {"device", "host", "completion"})
          .Add("stamp_offset", [](C& c) -> double& { return c.camera.stamp_offset_s; })
          .Add("frame_id", [](C& c) -> std::string& { return c.camera.frame_id; })
          .Add("camera_info_url", [](C& c) -> std::string& { return c.camera_info_url; })
          .Add("camera_info_name", [](C& c) -> std::string& { return c.camera_info_name; });
  return table;
}

NodeConfig LoadConfig(const ros::NodeHandle& pnh) {
  NodeConfig c;
  rig_model::LoadParams(pnh, Params(), &c);
  const std::string error = Validate(c.camera);
  if (!error.empty()) throw std::invalid_argument(error);
  return c;
}

CameraLiveConfig ToLive(const NodeConfig& c) {
  return rig_model::ToReconfigure<NodeConfig, CameraLiveConfig>(Params(), c);
}

NodeConfig FromLive(const CameraLiveConfig& live, NodeConfig c) {
  rig_model::FromReconfigure(Params(), live, &c);
  return c;
}

}  // namespace aravis_camera
