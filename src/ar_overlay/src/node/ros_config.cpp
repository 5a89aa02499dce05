#include "ar_overlay/node/ros_config.h"

#include <fstream>
#include <stdexcept>

#include "rig_model/ros/conversions.h"

namespace ar_overlay {

CameraModel FromCameraInfo(const sensor_msgs::CameraInfo& info) {
  CameraModel camera;
  std::string why;
  if (!rig_model::FromCameraInfo(info, &camera, &why)) throw std::invalid_argument(why);
  return camera;
}

std::string LoadConfig(const ros::NodeHandle& nh, OverlayConfig& c) {
  nh.param("scene_yaml", c.scene_yaml, c.scene_yaml);
  nh.param("fixed_frame", c.fixed_frame, c.fixed_frame);
  nh.param("camera_frame", c.camera_frame, c.camera_frame);
  std::string mode = c.pose_mode == PoseMode::kPredicted ? "predicted" : "image_stamp";
  nh.param("pose_mode", mode, mode);
  nh.param("tf_timeout_s", c.tf_timeout_s, c.tf_timeout_s);
  nh.param("render_rate_hz", c.render_rate_hz, c.render_rate_hz);
  nh.param("display_latency_s", c.display_latency_s, c.display_latency_s);
  nh.param("max_prediction_s", c.max_prediction_s, c.max_prediction_s);
  nh.param("velocity_window_s", c.velocity_window_s, c.velocity_window_s);
  nh.param("near_m", c.near_m, c.near_m);
  nh.param("far_m", c.far_m, c.far_m);
  nh.param("lod_max_error_px", c.lod_max_error_px, c.lod_max_error_px);
  nh.param("show_window", c.show_window, c.show_window);
  nh.param("window_name", c.window_name, c.window_name);

  if (mode == "image_stamp")
    c.pose_mode = PoseMode::kImageStamp;
  else if (mode == "predicted")
    c.pose_mode = PoseMode::kPredicted;
  else
    return "pose_mode '" + mode + "' is neither image_stamp nor predicted";
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
