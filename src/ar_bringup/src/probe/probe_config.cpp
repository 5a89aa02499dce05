#include "ar_bringup/probe_config.h"

#include "rig_model/ros/param_table_ros.h"

namespace ar_bringup {

const rig_model::ParamTable<ProbeConfig>& ProbeParams() {
  using C = ProbeConfig;
  static const rig_model::ParamTable<C> table =
      rig_model::ParamTable<C>()
          .Add("output_file", [](C& c) -> std::string& { return c.output_file; })
          .Add("fixed_frame", [](C& c) -> std::string& { return c.fixed_frame; })
          .Add("camera_frame", [](C& c) -> std::string& { return c.camera_frame; });
  return table;
}

ProbeConfig LoadProbeConfig(const ros::NodeHandle& pnh) {
  ProbeConfig c;
  rig_model::LoadParams(pnh, ProbeParams(), &c);
  return c;
}

}  // namespace ar_bringup
