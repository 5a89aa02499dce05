#include "rig_model/ros/params.h"

#include <algorithm>
#include <stdexcept>

#include "rig_model/strict_yaml.h"

namespace rig_model {

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
