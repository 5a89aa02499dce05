// The latency probe nodelet's private parameters: one struct, one parameter table.
#pragma once

#include <ros/node_handle.h>

#include <string>

#include "rig_model/param_table.h"

namespace ar_bringup {

struct ProbeConfig {
  std::string output_file;            // JSON rewritten once a second; "" writes nothing
  std::string fixed_frame = "cones";  // the tf edge whose stamps the probe times
  std::string camera_frame = "camera_optical";
};

const rig_model::ParamTable<ProbeConfig>& ProbeParams();

// rig_model::LoadParams: throws std::invalid_argument naming a parameter of the wrong type or an
// unknown (misspelt) one.
ProbeConfig LoadProbeConfig(const ros::NodeHandle& pnh);

}  // namespace ar_bringup
