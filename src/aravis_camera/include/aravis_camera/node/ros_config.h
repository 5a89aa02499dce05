// Reads CameraConfig from the node's private parameters (~camera_name, ...).
#pragma once

#include <ros/node_handle.h>

#include "aravis_camera/core/camera_config.h"

namespace aravis_camera {

// Throws std::invalid_argument with a message naming the bad parameter.
CameraConfig LoadConfig(const ros::NodeHandle& pnh);

}  // namespace aravis_camera
