// Type-checked ROS parameters: one loader and one error convention for every component.
// roscpp's getParam() silently truncates 2.5 to an int and gives no reason for a wrong type;
// these throw std::invalid_argument naming the parameter and the type it must have.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include <ros/node_handle.h>

namespace rig_model {

// Each reads `~name` into *value when the parameter exists; when it is absent, *value keeps the
// default the Config struct gave it. Doubles accept integers and the string "nan" (or ""),
// integers accept whole doubles.
void GetParam(const ros::NodeHandle& nh, const std::string& name, double* value);
void GetParam(const ros::NodeHandle& nh, const std::string& name, int* value);
void GetParam(const ros::NodeHandle& nh, const std::string& name, bool* value);
void GetParam(const ros::NodeHandle& nh, const std::string& name, std::string* value);

// An enum: `~name` holds one of `names` or its index, the int dynamic_reconfigure writes back for a
// .cfg enum whose constants are 0, 1, 2, ... in the order of `names`. Absent: *index keeps its default.
// Throws std::invalid_argument listing the accepted names and indices.
void GetEnumParam(const ros::NodeHandle& nh, const std::string& name, const std::vector<std::string>& names,
                  int* index);

// Throws std::invalid_argument for the first parameter under nh's namespace (one level deep) that
// is not in `known`: "parameter ~sigma_gyr_rad_s is unknown (did you mean ~sigma_gyro_rad_s?)".
// A known name covers everything under it (~debug_image/...); a known nested name such as
// "time_sync/window_s" is compared in full, so ~time_sync/windw_s is refused by its full name.
void CheckParamNames(const ros::NodeHandle& nh, const std::vector<std::string>& known);

}  // namespace rig_model
