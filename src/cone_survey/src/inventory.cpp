#include "cone_survey/inventory.h"

#include <cmath>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "rig_model/layout_yaml.h"
#include "rig_model/strict_yaml.h"

namespace cone_survey {
namespace {

using rig_model::ConeStyle;
using rig_model::FieldPath;
using rig_model::StrictReader;

int ReadIndex(const StrictReader& r, const YAML::Node& root, const char* key, int fallback, int n) {
  const double v = r.Number(root, "", key, fallback);
  if (v != std::floor(v) || v < 0 || v >= n)
    r.Fail(root[key] ? root[key] : root, key,
           "must be the index of one of the " + std::to_string(n) + " cones (0.." + std::to_string(n - 1) + ")");
  return static_cast<int>(v);
}

// The cones through rig_model's layout parser (the layout schema without positions), so a cone's
// fields are described and checked in one place; origin and x_axis are the inventory's own.
Inventory ParseRoot(const YAML::Node& root, const std::string& source) {
  const StrictReader r(source);
  if (!root || root.IsNull()) r.Fail(root, "cones", "empty inventory: give 'cones:' with {height_m, style} per cone");
  rig_model::LayoutSchema schema;
  schema.positions = false;
  schema.no_positions_why = "an inventory gives no positions: the survey measures them";
  schema.height_required = true;
  schema.what = "inventory";
  schema.extra_top_keys = {"origin", "x_axis"};
  Inventory inv;
  inv.cones = rig_model::ParseLayoutRoot(root, source, schema).cones;
  const int n = static_cast<int>(inv.cones.size());
  inv.origin = ReadIndex(r, root, "origin", 0, n);
  inv.x_axis = ReadIndex(r, root, "x_axis", 1, n);
  if (inv.origin == inv.x_axis) r.Fail(root["x_axis"] ? root["x_axis"] : root, "x_axis", "must differ from origin");
  for (const char* key : {"origin", "x_axis"}) {
    const int i = std::string(key) == "origin" ? inv.origin : inv.x_axis;
    for (int j = 0; j < n; ++j)
      if (j != i && std::abs(inv.cones[j].height_m - inv.cones[i].height_m) < 0.02)
        r.Fail(root[key] ? root[key] : root, key,
               inv.Name(i) + " shares its height with " + inv.Name(j) +
                   ": the survey tells cones apart by height, so the frame's anchors need heights of their own");
  }
  return inv;
}

}  // namespace

std::string Inventory::Name(int i) const {
  std::ostringstream s;
  s << "cones[" << i << "] (" << cones[i].height_m << " m " << (cones[i].style == ConeStyle::kRoad ? "road" : "plain")
    << ")";
  return s.str();
}

Inventory LoadInventoryFile(const std::string& path) { return ParseRoot(rig_model::LoadYamlFile(path), path); }

Inventory ParseInventory(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw rig_model::FileError(source + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML: " + e.msg);
  }
  return ParseRoot(root, source);
}

std::string InventoryYaml(const std::vector<rig_model::ConeSpec>& cones, int origin, int x_axis) {
  std::ostringstream y;
  y << "cones:\n";
  for (const rig_model::ConeSpec& c : cones) {
    y << "  - {height_m: " << c.height_m << ", style: " << (c.style == ConeStyle::kRoad ? "road" : "plain");
    if (std::abs(c.tau - rig_model::ConeSpec().tau) > 1e-9) y << ", tau: " << c.tau;
    y << "}\n";
  }
  y << "origin: " << origin << "\nx_axis: " << x_axis << "\n";
  return y.str();
}

}  // namespace cone_survey
