// The names under a component's private namespace. Its values are read through its parameter
// table (rig_model/ros/param_table_ros.h: LoadParams), which calls this first.
#pragma once

#include <string>
#include <vector>

#include <ros/node_handle.h>

namespace rig_model {

// Throws std::invalid_argument for the first parameter under nh's namespace (one level deep) that
// is not in `known`: "parameter ~sigma_gyr_rad_s is unknown (did you mean ~sigma_gyro_rad_s?)".
// A known name covers everything under it (~debug_image/...); a known nested name such as
// "time_sync/window_s" is compared in full, so ~time_sync/windw_s is refused by its full name.
void CheckParamNames(const ros::NodeHandle& nh, const std::vector<std::string>& known);

}  // namespace rig_model
