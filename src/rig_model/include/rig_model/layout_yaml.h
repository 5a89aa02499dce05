// The layout parser (layout.h) on a parsed YAML root, for files whose `cones:` list is the layout's:
// cone_survey's inventory is the layout schema without positions (its cones' height_m, style, tau, ...
// read and checked by the same code as a layout's), plus keys the inventory reads itself. One
// description of a cone's fields. ROS-free.
#pragma once

#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "rig_model/layout.h"

namespace rig_model {

// What a file of the layout schema may hold. The defaults are a layout file's.
struct LayoutSchema {
  // false: a cone's x_m, y_m, z_m and sigma_m are refused with `no_positions_why`, and the keys that
  // place cones or scenery (equilateral, boxes, patches, people, platforms, ground) are unknown keys;
  // cones of one height are not "identical" then (they stand nowhere yet).
  bool positions = true;
  std::string no_positions_why = "this file gives no positions";
  bool height_required = false;             // true: a cone without height_m is refused (else 0.71 m)
  std::string what = "layout";              // names the file's kind in the cone-count message
  std::vector<std::string> extra_top_keys;  // top-level keys the caller reads itself from the root
};

// Throws FileError naming the source, the line and the field, as LoadLayoutFile does.
Layout ParseLayoutRoot(const YAML::Node& root, const std::string& source, const LayoutSchema& schema);

}  // namespace rig_model
