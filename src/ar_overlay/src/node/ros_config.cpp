#include "ar_overlay/node/ros_config.h"

#include <fstream>
#include <stdexcept>

#include "rig_model/ros/conversions.h"
#include "rig_model/ros/param_table_ros.h"

namespace ar_overlay {

CameraModel FromCameraInfo(const sensor_msgs::CameraInfo& info) {
  CameraModel camera;
  std::string why;
  if (!rig_model::FromCameraInfo(info, &camera, &why)) throw std::invalid_argument(why);
  return camera;
}

const rig_model::ParamTable<OverlayConfig>& Params() {
  using C = OverlayConfig;
  static const rig_model::ParamTable<C> table =
      rig_model::ParamTable<C>()
          .Add("scene_yaml", [](C& c) -> std::string& { return c.scene_yaml; })
          .Add("fixed_frame", [](C& c) -> std::string& { return c.fixed_frame; })
          .Add("camera_frame", [](C& c) -> std::string& { return c.camera_frame; })
          .AddEnum("pose_mode", [](C& c) -> int& { return c.pose_mode; }, {"image_stamp", "predicted"})
          .Add("tf_timeout_s", [](C& c) -> double& { return c.tf_timeout_s; })
          .Add("render_rate_hz", [](C& c) -> double& { return c.render_rate_hz; })
          .Add("display_latency_s", [](C& c) -> double& { return c.display_latency_s; })
          .Add("max_prediction_s", [](C& c) -> double& { return c.max_prediction_s; })
          .Add("velocity_window_s", [](C& c) -> double& { return c.velocity_window_s; })
          .Add("near_m", [](C& c) -> double& { return c.near_m; })
          .Add("far_m", [](C& c) -> double& { return c.far_m; })
          .Add("lod_max_error_px", [](C& c) -> double& { return c.lod_max_error_px; })
          .Add("show_window", [](C& c) -> bool& { return c.show_window; })
          .Add("window_name", [](C& c) -> std::string& { return c.window_name; });
  return table;
}

std::string LoadConfig(const ros::NodeHandle& nh, OverlayConfig& c) {
  try {
    rig_model::LoadParams(nh, Params(), &c, {"image"});  // ~image/...: image_transport's plugins' own
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  if (!c.scene_yaml.empty() && !std::ifstream(c.scene_yaml)) return "scene_yaml '" + c.scene_yaml + "' cannot be read";
  if (c.fixed_frame.empty()) return "fixed_frame is empty";
  if (!(c.tf_timeout_s >= 0 && c.tf_timeout_s <= 1)) return "tf_timeout_s must be in [0, 1]";
  if (!(c.render_rate_hz > 0 && c.render_rate_hz <= 240)) return "render_rate_hz must be in (0, 240]";
  if (!(c.display_latency_s >= 0 && c.display_latency_s <= 1)) return "display_latency_s must be in [0, 1]";
  if (!(c.max_prediction_s >= 0 && c.max_prediction_s <= 1)) return "max_prediction_s must be in [0, 1]";
  if (!(c.velocity_window_s > 0 && c.velocity_window_s <= 1)) return "velocity_window_s must be in (0, 1]";
  if (!(c.near_m > 0 && c.far_m > c.near_m)) return "near_m and far_m need 0 < near_m < far_m";
  if (!(c.lod_max_error_px >= 0 && c.lod_max_error_px <= 100)) return "lod_max_error_px must be in [0, 100]";
  return "";
}

}  // namespace ar_overlay
