// The survey's inventory: the placed cones without positions, and which one is the origin of the
// `cones` frame and which one marks +x. A layout file's `cones:` list of {height_m, style} (height_m
// required; any other cone key of the layout schema, such as tau, except the positions x_m, y_m, z_m and
// sigma_m; read by rig_model's layout parser, layout_yaml.h), no scenery, plus two indices into it:
//
//   cones:
//     - {height_m: 0.91, style: road}
//     - {height_m: 0.30, style: plain}
//     - {height_m: 0.71, style: road}
//   origin: 0   # cones[0] stands at (0, 0, 0)
//   x_axis: 1   # cones[1] lies on +x
//
// The origin and the +x cone must be the only ones of their height: the survey tells cones apart by
// height, so a cone that shares its height with another cannot anchor the frame. ROS-free.
#pragma once

#include <string>
#include <vector>

#include "rig_model/layout.h"

namespace cone_survey {

struct Inventory {
  std::vector<rig_model::ConeSpec> cones;  // base_m zero
  int origin = 0;
  int x_axis = 1;
  // "cones[3] (0.46 m plain)": how messages name an entry.
  std::string Name(int i) const;
};

// Throws rig_model::FileError naming the file, line and field (unknown keys with the nearest known
// one, positions given, bad indices, an origin or +x cone that shares its height).
Inventory LoadInventoryFile(const std::string& path);
Inventory ParseInventory(const std::string& yaml_text, const std::string& source);

// The inventory of a layout (its cones without positions), origin and +x as given, as YAML text.
std::string InventoryYaml(const std::vector<rig_model::ConeSpec>& cones, int origin, int x_axis);

}  // namespace cone_survey
