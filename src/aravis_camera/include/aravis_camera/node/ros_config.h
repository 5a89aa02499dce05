// The camera nodelet's settings from its private parameters (~camera_name, ...): one parameter
// table (Params()) read by rig_model::LoadParams, the same names dynamic_reconfigure uses.
#pragma once

#include <ros/node_handle.h>

#include <string>

#include "aravis_camera/CameraLiveConfig.h"
#include "aravis_camera/core/camera_config.h"
#include "rig_model/param_table.h"

namespace aravis_camera {

// The device's settings plus the nodelet's own (camera_info_manager's calibration).
struct NodeConfig {
  CameraConfig camera;
  std::string camera_info_url;              // "": camera_info_manager's default location
  std::string camera_info_name = "camera";  // camera_calibration names its files after the camera
};

// Every private parameter: its ROS name (no unit suffix, as the README and CameraLive.cfg have
// them; the struct fields carry the units) and its field.
const rig_model::ParamTable<NodeConfig>& Params();

// Throws std::invalid_argument with a message naming the bad parameter: a wrong type, an unknown
// (misspelt) name, or a value Validate refuses.
NodeConfig LoadConfig(const ros::NodeHandle& pnh);

// The live settings, through the table by name: the dynamic_reconfigure server's start values,
// and `c` with what the server sends back.
CameraLiveConfig ToLive(const NodeConfig& c);
NodeConfig FromLive(const CameraLiveConfig& live, NodeConfig c);

}  // namespace aravis_camera
