// cone_tracker's one parameter table: NodeConfig's fields under the names of the nodelet's private
// parameters, in the units those names carry. LoadConfig (ROS parameters), the nodelet's
// dynamic_reconfigure server (cfg/ConeTracker.cfg) and detect_cones (YAML) all read through it.
// ROS-free.
#pragma once

#include <string>

#include "cone_tracker/node/node_config.h"
#include "rig_model/param_table.h"

namespace cone_tracker {

const rig_model::ParamTable<NodeConfig>& NodeParams();

// A YAML file of the nodelet's parameters (detect_cones --config, tests): the same names and units,
// through the table; unknown or misspelt keys, wrong types and non-finite numbers are refused with the
// file, line and key (rig_model::FileError). A relative `colour_model` is the file's neighbour.
NodeConfig LoadConfigFile(const std::string& path);

}  // namespace cone_tracker
