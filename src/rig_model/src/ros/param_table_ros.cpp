#include "rig_model/ros/param_table_ros.h"

#include <limits>

namespace rig_model {

bool FetchParam(const ros::NodeHandle& nh, const std::string& name, ParamValue* value) {
  XmlRpc::XmlRpcValue v;
  if (!nh.hasParam(name) || !nh.getParam(name, v)) return false;
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      *value = static_cast<bool>(v);
      return true;
    case XmlRpc::XmlRpcValue::TypeInt:
      *value = static_cast<int>(v);
      return true;
    case XmlRpc::XmlRpcValue::TypeDouble:
      *value = static_cast<double>(v);
      return true;
    case XmlRpc::XmlRpcValue::TypeString: {
      const std::string s = v;
      // YAML's .nan reaches the parameter server as a string when written as "nan" in a launch file.
      if (s == "nan" || s == ".nan") {
        *value = std::numeric_limits<double>::quiet_NaN();
      } else {
        *value = s;
      }
      return true;
    }
    default:
      throw std::invalid_argument(name + " must be a single value, not a list or a mapping");
  }
}

void WriteReconfigureMessage(const std::function<ParamValue(const std::string&)>& get,
                             dynamic_reconfigure::Config* msg) {
  for (auto& p : msg->doubles) {
    const ParamValue v = get(p.name);
    if (const double* d = std::get_if<double>(&v)) p.value = *d;
    if (const int* i = std::get_if<int>(&v)) p.value = *i;
  }
  for (auto& p : msg->ints) {
    const ParamValue v = get(p.name);
    if (const int* i = std::get_if<int>(&v)) p.value = *i;
  }
  for (auto& p : msg->bools) {
    const ParamValue v = get(p.name);
    if (const bool* b = std::get_if<bool>(&v)) p.value = *b;
  }
  for (auto& p : msg->strs) {
    const ParamValue v = get(p.name);
    if (const std::string* s = std::get_if<std::string>(&v)) p.value = *s;
  }
}

void ReadReconfigureMessage(const dynamic_reconfigure::Config& msg,
                            const std::function<void(const std::string&, const ParamValue&)>& set) {
  for (const auto& p : msg.doubles) set(p.name, p.value);
  for (const auto& p : msg.ints) set(p.name, static_cast<int>(p.value));
  for (const auto& p : msg.bools) set(p.name, static_cast<bool>(p.value));
  for (const auto& p : msg.strs) set(p.name, p.value);
}

}  // namespace rig_model
