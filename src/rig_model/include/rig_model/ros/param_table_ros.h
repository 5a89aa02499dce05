// The ROS sides of a component's ParamTable: private parameters and dynamic_reconfigure.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <dynamic_reconfigure/Config.h>
#include <ros/node_handle.h>

#include "rig_model/param_table.h"
#include "rig_model/ros/params.h"

namespace rig_model {

// ~name as a ParamValue; false when absent. Throws std::invalid_argument for a list or a mapping.
bool FetchParam(const ros::NodeHandle& nh, const std::string& name, ParamValue* value);

// Fills every parameter of a dynamic_reconfigure message (one its Config type wrote) through `get`,
// converting to the message's type for that name.
void WriteReconfigureMessage(const std::function<ParamValue(const std::string&)>& get,
                             dynamic_reconfigure::Config* msg);
// Calls `set` with every parameter of the message.
void ReadReconfigureMessage(const dynamic_reconfigure::Config& msg,
                            const std::function<void(const std::string&, const ParamValue&)>& set);

// Reads the table's parameters from `pnh` into `config` (absent ones keep the struct's defaults).
// Throws std::invalid_argument naming the parameter: "parameter ~max_tilt_deg must be a number",
// also for a parameter under ~ that the table does not know (a typo in a launch or YAML file).
// Table names may be nested ("time_sync/window_s"). `also_known`: other names or sub-namespaces
// under ~ that the component reads itself (lists, files) or someone else reads (image_transport's),
// checked for spelling all the same.
template <class Config>
void LoadParams(const ros::NodeHandle& pnh, const ParamTable<Config>& table, Config* config,
                const std::vector<std::string>& also_known = {}) {
  std::vector<std::string> known = table.Names();
  known.insert(known.end(), also_known.begin(), also_known.end());
  known.push_back("diagnostic_period");  // diagnostic_updater::Updater reads it from the same namespace
  CheckParamNames(pnh, known);
  for (const std::string& name : table.Names()) {
    ParamValue value;
    try {
      if (FetchParam(pnh, name, &value)) table.Set(config, name, value);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("parameter ~") + e.what());
    }
  }
}

// dynamic_reconfigure's generated Config types (Reconfigure) <-> the component's Config, by name.
// Every reconfigurable name must be in the table; throws std::invalid_argument naming one that is not.
template <class Config, class Reconfigure>
Reconfigure ToReconfigure(const ParamTable<Config>& table, const Config& config) {
  Reconfigure r = Reconfigure::__getDefault__();
  dynamic_reconfigure::Config msg;
  r.__toMessage__(msg);
  WriteReconfigureMessage([&](const std::string& name) { return table.Get(config, name); }, &msg);
  r.__fromMessage__(msg);
  return r;
}

template <class Config, class Reconfigure>
void FromReconfigure(const ParamTable<Config>& table, const Reconfigure& r, Config* config) {
  dynamic_reconfigure::Config msg;
  r.__toMessage__(msg);
  ReadReconfigureMessage(msg, [&](const std::string& name, const ParamValue& v) { table.Set(config, name, v); });
}

}  // namespace rig_model
