#include "cone_tracker/node/layout.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

namespace cone_tracker {
namespace {

// A field of a mapping, or the fallback when absent; names the field on a bad value.
double ReadDouble(const YAML::Node& parent, const std::string& where, const char* key, double fallback) {
  const YAML::Node n = parent[key];
  if (!n) return fallback;
  double v = 0.0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(where + "." + key + " must be a number (line " + std::to_string(n.Mark().line + 1) + ")");
  }
  if (!std::isfinite(v)) throw std::runtime_error(where + "." + key + " must be finite");
  return v;
}

void CheckStyle(const YAML::Node& parent, const std::string& where) {
  const YAML::Node n = parent["style"];
  if (!n) return;
  const std::string s = n.IsScalar() ? n.Scalar() : "";
  if (s != "road" && s != "plain")
    throw std::runtime_error(where + ".style must be 'road' or 'plain', got '" + s + "'");
}

void CheckMap(const YAML::Node& n, const std::string& where) {
  if (!n.IsMap()) throw std::runtime_error(where + " must be a mapping like {x_m: 1.0, y_m: 0.0, height_m: 0.71}");
}

ConeModel ReadCone(const YAML::Node& n, const std::string& where) {
  CheckMap(n, where);
  CheckStyle(n, where);
  ConeModel c;
  c.base_m = Eigen::Vector3d(ReadDouble(n, where, "x_m", 0.0), ReadDouble(n, where, "y_m", 0.0),
                             ReadDouble(n, where, "z_m", 0.0));
  c.height_m = ReadDouble(n, where, "height_m", 0.71);
  c.tau = ReadDouble(n, where, "tau", c.tau);
  if (!(c.tau > 0.02 && c.tau < 1.0)) throw std::runtime_error(where + ".tau must be in (0.02, 1)");
  return c;
}

std::vector<ConeModel> ParseRoot(const YAML::Node& root, const LayoutLimits& lim) {
  if (!root.IsMap()) throw std::runtime_error("the file must be a YAML mapping with 'cones:' or 'equilateral:'");
  std::vector<ConeModel> cones;
  if (const YAML::Node e = root["equilateral"]) {
    CheckMap(e, "equilateral");
    CheckStyle(e, "equilateral");
    const double side = ReadDouble(e, "equilateral", "side_m", 1.5);
    const double h = ReadDouble(e, "equilateral", "height_m", 0.71);
    if (!(side > 0.0)) throw std::runtime_error("equilateral.side_m must be > 0");
    const double circumradius = side / std::sqrt(3.0);  // same construction as rig_sim's EquilateralScene
    for (int i = 0; i < 3; ++i) {
      ConeModel c;
      const double a = 2.0 * M_PI * i / 3.0;
      c.base_m = Eigen::Vector3d(circumradius * std::cos(a), circumradius * std::sin(a), 0.0);
      c.height_m = h;
      cones.push_back(c);
    }
  }
  if (const YAML::Node list = root["cones"]) {
    if (!list.IsSequence()) throw std::runtime_error("cones must be a list of {x_m, y_m, height_m, ...}");
    for (size_t i = 0; i < list.size(); ++i) cones.push_back(ReadCone(list[i], "cones[" + std::to_string(i) + "]"));
  }
  if (cones.empty()) throw std::runtime_error("no cones: give 'cones:' or 'equilateral:'");
  if (int(cones.size()) < lim.min_cones || int(cones.size()) > lim.max_cones) {
    throw std::runtime_error("the layout has " + std::to_string(cones.size()) + " cones; " +
                             std::to_string(lim.min_cones) + " to " + std::to_string(lim.max_cones) + " are supported");
  }
  for (size_t i = 0; i < cones.size(); ++i) {
    const double h = cones[i].height_m;
    if (h < lim.min_height_m - 1e-9 || h > lim.max_height_m + 1e-9) {
      std::ostringstream m;
      m << "cone " << i << " (file order, equilateral first): height_m " << h << " is outside [" << lim.min_height_m
        << ", " << lim.max_height_m << "] m";
      throw std::runtime_error(m.str());
    }
    for (size_t j = 0; j < i; ++j) {
      if ((cones[i].base_m - cones[j].base_m).norm() < 1e-6 && std::abs(h - cones[j].height_m) < 1e-6)
        throw std::runtime_error("cones " + std::to_string(j) + " and " + std::to_string(i) + " are identical");
    }
  }
  return cones;
}

}  // namespace

bool ParseLayout(const std::string& text, const std::string& source, std::vector<ConeModel>* cones,
                 std::string* error) {
  try {
    *cones = ParseRoot(YAML::Load(text), LayoutLimits());
    return true;
  } catch (const YAML::Exception& e) {
    if (error) *error = "layout " + source + ": not valid YAML: " + e.what();
  } catch (const std::exception& e) {
    if (error) *error = "layout " + source + ": " + e.what();
  }
  return false;
}

bool LoadLayoutFile(const std::string& path, std::vector<ConeModel>* cones, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    if (error) *error = "cannot open layout file '" + path + "' (parameter layout_file)";
    return false;
  }
  std::stringstream ss;
  ss << in.rdbuf();
  return ParseLayout(ss.str(), "'" + path + "'", cones, error);
}

}  // namespace cone_tracker
