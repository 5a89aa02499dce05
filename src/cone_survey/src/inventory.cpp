#include "cone_survey/inventory.h"

#include <cmath>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "rig_model/strict_yaml.h"

namespace cone_survey {
namespace {

using rig_model::ConeStyle;
using rig_model::FieldPath;
using rig_model::StrictReader;

const std::vector<std::string> kTopKeys = {"cones", "origin", "x_axis"};
// Positions are what the survey measures: an inventory gives none (the message says so).
const std::vector<std::string> kConeKeys = {"height_m", "style", "tau"};

int ReadIndex(const StrictReader& r, const YAML::Node& root, const char* key, int fallback, int n) {
  const double v = r.Number(root, "", key, fallback);
  if (v != std::floor(v) || v < 0 || v >= n)
    r.Fail(root[key] ? root[key] : root, key,
           "must be the index of one of the " + std::to_string(n) + " cones (0.." + std::to_string(n - 1) + ")");
  return static_cast<int>(v);
}

Inventory ParseRoot(const YAML::Node& root, const std::string& source) {
  const StrictReader r(source);
  if (!root || root.IsNull()) r.Fail(root, "cones", "empty inventory: give 'cones:' with {height_m, style} per cone");
  r.CheckKeys(root, kTopKeys, "");
  const YAML::Node list = root["cones"];
  if (!list || !list.IsSequence())
    r.Fail(list ? list : root, "cones", "must be a list like [{height_m: 0.71, style: road}]");
  Inventory inv;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string where = "cones[" + std::to_string(i) + "]";
    const YAML::Node& n = list[i];
    for (const char* pos : {"x_m", "y_m", "z_m"})
      if (n.IsMap() && n[pos])
        r.Fail(n[pos], FieldPath(where, pos), "an inventory gives no positions: the survey measures them");
    r.CheckKeys(n, kConeKeys, where);
    const std::string style = r.String(n, where, "style", "road");
    if (style != "road" && style != "plain") r.Fail(n["style"], FieldPath(where, "style"), "must be 'road' or 'plain'");
    const double h = r.RequiredNumber(n, where, "height_m");
    if (h < rig_model::LayoutLimits::kMinHeightM || h > rig_model::LayoutLimits::kMaxHeightM) {
      std::ostringstream m;
      m << h << " is outside [" << rig_model::LayoutLimits::kMinHeightM << ", " << rig_model::LayoutLimits::kMaxHeightM
        << "] m";
      r.Fail(n["height_m"], FieldPath(where, "height_m"), m.str());
    }
    rig_model::ConeSpec c =
        rig_model::MakeCone(Eigen::Vector3d::Zero(), h, style == "road" ? ConeStyle::kRoad : ConeStyle::kPlain);
    c.tau = r.Number(n, where, "tau", c.tau);
    if (!(c.tau > 0.02 && c.tau < 1.0)) r.Fail(n["tau"], FieldPath(where, "tau"), "must be in (0.02, 1)");
    inv.cones.push_back(c);
  }
  const int n = static_cast<int>(inv.cones.size());
  if (n < rig_model::LayoutLimits::kMinCones || n > rig_model::LayoutLimits::kMaxCones)
    r.Fail(list, "cones",
           "the inventory has " + std::to_string(n) + " cones; a layout has " +
               std::to_string(rig_model::LayoutLimits::kMinCones) + " to " +
               std::to_string(rig_model::LayoutLimits::kMaxCones));
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
