// cone_tracker's one parameter table: NodeConfig's fields under the names of the nodelet's private
// parameters, in the units those names carry. LoadConfig (ROS parameters), the nodelet's
// dynamic_reconfigure server (cfg/ConeTracker.cfg) and detect_cones (YAML) all read through it.
// ROS-free.
#pragma once

#include "cone_tracker/node/node_config.h"
#include "rig_model/param_table.h"

namespace cone_tracker {

const rig_model::ParamTable<NodeConfig>& NodeParams();

}  // namespace cone_tracker
