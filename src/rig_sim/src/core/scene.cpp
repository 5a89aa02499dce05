#include "rig_sim/scene.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <yaml-cpp/yaml.h>

namespace rig_sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMinConeHeightM = 0.10;  // 4" indoor cone
constexpr double kMaxConeHeightM = 0.92;  // 36" road cone

Eigen::Vector3d ReadColor(const YAML::Node& n, const Eigen::Vector3d& fallback) {
  if (!n) return fallback;
  if (!n.IsSequence() || n.size() != 3) throw std::runtime_error("albedo must be [r, g, b]");
  Eigen::Vector3d c(n[0].as<double>(), n[1].as<double>(), n[2].as<double>());
  if ((c.array() < 0.0).any() || (c.array() > 1.0).any())
    throw std::runtime_error("albedo components must be in [0, 1]");
  return c;
}

double ReadDouble(const YAML::Node& parent, const char* key, double fallback) {
  const YAML::Node n = parent[key];
  if (!n) return fallback;
  const double v = n.as<double>();
  if (!std::isfinite(v)) throw std::runtime_error(std::string(key) + " must be finite");
  return v;
}

ConeSpec ReadCone(const YAML::Node& n) {
  const std::string style_name = n["style"] ? n["style"].as<std::string>() : "road";
  ConeStyle style;
  if (style_name == "road")
    style = ConeStyle::kRoad;
  else if (style_name == "plain")
    style = ConeStyle::kPlain;
  else
    throw std::runtime_error("style must be 'road' or 'plain', got '" + style_name + "'");
  const double h = ReadDouble(n, "height_m", 0.71);
  if (h < kMinConeHeightM - 1e-9 || h > kMaxConeHeightM)
    throw std::runtime_error("height_m must be in [0.10, 0.92] m (4\" to 36\")");
  const Eigen::Vector3d base(ReadDouble(n, "x_m", 0.0), ReadDouble(n, "y_m", 0.0), ReadDouble(n, "z_m", 0.0));
  ConeSpec cone = MakeCone(base, h, style);
  cone.tau = ReadDouble(n, "tau", cone.tau);
  if (!(cone.tau > 0.02 && cone.tau < 1.0)) throw std::runtime_error("tau must be in (0.02, 1)");
  cone.albedo = ReadColor(n["albedo"], cone.albedo);
  cone.base_plate_m = ReadDouble(n, "base_plate_m", cone.base_plate_m);
  if (n["collars"]) {
    cone.collars.clear();
    for (const auto& c : n["collars"]) {
      const double a = c[0].as<double>(), b = c[1].as<double>();
      if (!(a >= 0.0 && b <= 1.0 && a < b)) throw std::runtime_error("collars must be [from, to] in [0, 1]");
      cone.collars.emplace_back(a, b);
    }
  }
  return cone;
}

void ParseRoot(const YAML::Node& root, Scene* out) {
  Scene s;
  if (root["equilateral"]) {
    const YAML::Node e = root["equilateral"];
    const std::string style = e["style"] ? e["style"].as<std::string>() : "road";
    s = EquilateralScene(ReadDouble(e, "side_m", 1.5), ReadDouble(e, "height_m", 0.71),
                         style == "plain" ? ConeStyle::kPlain : ConeStyle::kRoad);
    if (style != "plain" && style != "road") throw std::runtime_error("equilateral.style must be road or plain");
  }
  if (root["cones"]) {
    int i = 0;
    for (const auto& c : root["cones"]) {
      try {
        s.cones.push_back(ReadCone(c));
      } catch (const std::exception& e) {
        throw std::runtime_error("cones[" + std::to_string(i) + "]: " + e.what());
      }
      ++i;
    }
  }
  if (s.cones.empty()) throw std::runtime_error("no cones: give 'cones:' or 'equilateral:'");
  for (const auto& b : root["boxes"]) {
    BoxSpec box;
    box.size_m = Eigen::Vector3d(ReadDouble(b, "sx_m", 0.4), ReadDouble(b, "sy_m", 0.3), ReadDouble(b, "sz_m", 0.3));
    box.center_m = Eigen::Vector3d(ReadDouble(b, "x_m", 0.0), ReadDouble(b, "y_m", 0.0), 0.5 * box.size_m.z());
    box.yaw_rad = ReadDouble(b, "yaw_deg", 0.0) * kPi / 180.0;
    box.albedo = ReadColor(b["albedo"], box.albedo);
    if ((box.size_m.array() <= 0.0).any()) throw std::runtime_error("boxes: sizes must be positive");
    s.boxes.push_back(box);
  }
  for (const auto& p : root["patches"]) {
    PatchSpec patch;
    patch.center_m = Eigen::Vector2d(ReadDouble(p, "x_m", 0.0), ReadDouble(p, "y_m", 0.0));
    patch.size_m = Eigen::Vector2d(ReadDouble(p, "sx_m", 0.5), ReadDouble(p, "sy_m", 0.5));
    patch.yaw_rad = ReadDouble(p, "yaw_deg", 0.0) * kPi / 180.0;
    patch.albedo = ReadColor(p["albedo"], patch.albedo);
    if ((patch.size_m.array() <= 0.0).any()) throw std::runtime_error("patches: sizes must be positive");
    s.patches.push_back(patch);
  }
  for (const auto& p : root["people"]) {
    PersonSpec person;
    person.position_m = Eigen::Vector2d(ReadDouble(p, "x_m", 0.0), ReadDouble(p, "y_m", 0.0));
    person.height_m = ReadDouble(p, "height_m", person.height_m);
    s.people.push_back(person);
  }
  int platform_index = 0;
  for (const auto& p : root["platforms"]) {
    const std::string where = "platforms[" + std::to_string(platform_index++) + "]: ";
    PlatformSpec pl;
    pl.center_m = Eigen::Vector2d(ReadDouble(p, "x_m", 0.0), ReadDouble(p, "y_m", 0.0));
    pl.yaw_rad = ReadDouble(p, "yaw_deg", 0.0) * kPi / 180.0;
    pl.size_m = Eigen::Vector3d(ReadDouble(p, "sx_m", pl.size_m.x()), ReadDouble(p, "sy_m", pl.size_m.y()),
                                ReadDouble(p, "sz_m", pl.size_m.z()));
    pl.albedo = ReadColor(p["albedo"], pl.albedo);
    pl.rows = p["rows"] ? p["rows"].as<int>() : pl.rows;
    pl.cols = p["cols"] ? p["cols"].as<int>() : pl.cols;
    pl.spacing_m = ReadDouble(p, "spacing_m", pl.spacing_m);
    pl.dot_radius_m = ReadDouble(p, "dot_radius_m", pl.dot_radius_m);
    pl.dot_albedo = ReadColor(p["dot_albedo"], pl.dot_albedo);
    if ((pl.size_m.array() <= 0.0).any()) throw std::runtime_error(where + "sizes must be positive");
    if (pl.rows < 1 || pl.cols < 1) throw std::runtime_error(where + "rows and cols must be at least 1");
    if (!(pl.dot_radius_m > 0.0) || !(pl.spacing_m > 2.0 * pl.dot_radius_m))
      throw std::runtime_error(where + "need 0 < dot_radius_m < spacing_m / 2");
    if ((pl.cols - 1) * pl.spacing_m + 2 * pl.dot_radius_m > pl.size_m.x() ||
        (pl.rows - 1) * pl.spacing_m + 2 * pl.dot_radius_m > pl.size_m.y())
      throw std::runtime_error(where + "the dot grid does not fit on the board");
    s.platforms.push_back(pl);
  }
  if (root["ground"]) {
    const std::string g = root["ground"].as<std::string>();
    if (g == "asphalt")
      s.ground = GroundStyle::kAsphalt;
    else if (g == "grass")
      s.ground = GroundStyle::kGrass;
    else if (g == "concrete")
      s.ground = GroundStyle::kConcrete;
    else
      throw std::runtime_error("ground must be asphalt, grass or concrete, got '" + g + "'");
  }
  *out = s;
}

}  // namespace

std::vector<Eigen::Vector3d> PlatformSpec::DotCentres() const {
  std::vector<Eigen::Vector3d> dots;
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < cols; ++k) {
      const double x = (k - 0.5 * (cols - 1)) * spacing_m, y = (r - 0.5 * (rows - 1)) * spacing_m;
      dots.emplace_back(center_m.x() + c * x - s * y, center_m.y() + s * x + c * y, size_m.z());
    }
  return dots;
}

Eigen::Vector3d Scene::ConeCentroid() const {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& cone : cones) c += cone.base_m;
  return cones.empty() ? c : Eigen::Vector3d(c / static_cast<double>(cones.size()));
}

ConeSpec MakeCone(const Eigen::Vector3d& base_m, double height_m, ConeStyle style) {
  ConeSpec c;
  c.base_m = base_m;
  c.height_m = height_m;
  c.style = style;
  if (style == ConeStyle::kRoad) {
    // 28"-36" cones carry a 6" upper and a 4" lower retroreflective collar.
    c.collars = {{0.42, 0.55}, {0.62, 0.80}};
    c.base_plate_m = 0.5 * height_m;
  }
  return c;
}

Scene EquilateralScene(double side_m, double height_m, ConeStyle style) {
  Scene s;
  const double circumradius = side_m / std::sqrt(3.0);
  for (int i = 0; i < 3; ++i) {
    const double a = 2.0 * kPi * i / 3.0;
    s.cones.push_back(
        MakeCone(Eigen::Vector3d(circumradius * std::cos(a), circumradius * std::sin(a), 0.0), height_m, style));
  }
  return s;
}

Scene DefaultScene() { return EquilateralScene(1.5, 0.71, ConeStyle::kRoad); }

bool ParseSceneYaml(const std::string& text, Scene* scene, std::string* error) {
  try {
    ParseRoot(YAML::Load(text), scene);
    return true;
  } catch (const std::exception& e) {
    if (error) *error = e.what();
    return false;
  }
}

bool LoadSceneYaml(const std::string& path, Scene* scene, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    if (error) *error = "cannot open layout file '" + path + "'";
    return false;
  }
  std::stringstream ss;
  ss << in.rdbuf();
  if (ParseSceneYaml(ss.str(), scene, error)) return true;
  if (error) *error = path + ": " + *error;
  return false;
}

}  // namespace rig_sim
