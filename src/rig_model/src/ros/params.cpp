#include "rig_model/ros/params.h"

#include <algorithm>
#include <cmath>

#include "rig_model/strict_yaml.h"

namespace rig_model {
namespace {

// Fetches ~name; false when it is absent.
bool Fetch(const ros::NodeHandle& nh, const std::string& name, XmlRpc::XmlRpcValue* v) {
  return nh.hasParam(name) && nh.getParam(name, *v);
}

[[noreturn]] void WrongType(const std::string& name, const std::string& must_be) {
  throw std::invalid_argument("parameter ~" + name + " must be " + must_be);
}

}  // namespace

void GetParam(const ros::NodeHandle& nh, const std::string& name, double* value) {
  XmlRpc::XmlRpcValue v;
  if (!Fetch(nh, name, &v)) return;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) {
    *value = static_cast<double>(v);
  } else if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) {
    *value = static_cast<int>(v);
  } else if (v.getType() == XmlRpc::XmlRpcValue::TypeString && (std::string(v) == "nan" || std::string(v).empty())) {
    *value = NAN;
  } else {
    WrongType(name, "a number");
  }
}

void GetParam(const ros::NodeHandle& nh, const std::string& name, int* value) {
  XmlRpc::XmlRpcValue v;
  if (!Fetch(nh, name, &v)) return;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) {
    *value = static_cast<int>(v);
  } else if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble && std::isfinite(double(v)) &&
             double(v) == std::round(double(v))) {
    *value = static_cast<int>(double(v));
  } else {
    WrongType(name, "an integer");
  }
}

void GetParam(const ros::NodeHandle& nh, const std::string& name, bool* value) {
  XmlRpc::XmlRpcValue v;
  if (!Fetch(nh, name, &v)) return;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeBoolean) WrongType(name, "true or false");
  *value = static_cast<bool>(v);
}

void GetParam(const ros::NodeHandle& nh, const std::string& name, std::string* value) {
  XmlRpc::XmlRpcValue v;
  if (!Fetch(nh, name, &v)) return;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeString) WrongType(name, "a string");
  *value = static_cast<std::string>(v);
}

void GetEnumParam(const ros::NodeHandle& nh, const std::string& name, const std::vector<std::string>& names,
                  int* index) {
  XmlRpc::XmlRpcValue v;
  if (!Fetch(nh, name, &v)) return;
  const int n = static_cast<int>(names.size());
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt && int(v) >= 0 && int(v) < n) {
    *index = static_cast<int>(v);
    return;
  }
  if (v.getType() == XmlRpc::XmlRpcValue::TypeString) {
    const auto it = std::find(names.begin(), names.end(), std::string(v));
    if (it != names.end()) {
      *index = static_cast<int>(it - names.begin());
      return;
    }
  }
  std::string list;
  for (int i = 0; i < n; ++i) list += (i ? ", " : "") + names[i] + " (" + std::to_string(i) + ")";
  std::string got = "a value of another type";
  if (v.getType() == XmlRpc::XmlRpcValue::TypeString) got = "'" + std::string(v) + "'";
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) got = std::to_string(int(v));
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) got = std::to_string(double(v));
  WrongType(name, "one of " + list + " (got " + got + ")");
}

void CheckParamNames(const ros::NodeHandle& nh, const std::vector<std::string>& known) {
  std::vector<std::string> all;
  if (!nh.getParamNames(all)) return;  // master unreachable: the loads that follow say so
  const std::string prefix = nh.getNamespace() + "/";
  for (const std::string& full : all) {
    if (full.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = full.substr(prefix.size());
    const std::string first = rest.substr(0, rest.find('/'));
    const auto is_known = [&](const std::string& n) { return std::find(known.begin(), known.end(), n) != known.end(); };
    if (is_known(first) || is_known(rest)) continue;
    // A known nested name ("time_sync/window_s") makes its namespace's other names checked in full.
    const bool nested = std::any_of(known.begin(), known.end(), [&](const std::string& k) {
      return k.compare(0, first.size() + 1, first + "/") == 0;
    });
    const std::string name = nested ? rest : first;
    const std::string nearest = NearestKey(name, known);
    throw std::invalid_argument("parameter ~" + name + " is unknown" +
                                (nearest.empty() ? "" : " (did you mean ~" + nearest + "?)"));
  }
}

}  // namespace rig_model
