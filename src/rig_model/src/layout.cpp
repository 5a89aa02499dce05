#include "rig_model/layout.h"

#include <cmath>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "rig_model/layout_yaml.h"
#include "rig_model/strict_yaml.h"
#include "rig_model/surveyed_layout.h"

namespace rig_model {
namespace {

constexpr double kPi = 3.14159265358979323846;

const std::vector<std::string> kTopKeys = {"equilateral", "cones", "boxes", "patches", "people", "platforms", "ground"};
const std::vector<std::string> kEquilateralKeys = {"side_m", "height_m", "style"};
const std::vector<std::string> kConeKeys = {"x_m",   "y_m",    "z_m",     "height_m",     "tau",
                                            "style", "albedo", "collars", "base_plate_m", "sigma_m"};
const std::vector<std::string> kBoxKeys = {"x_m", "y_m", "yaw_deg", "sx_m", "sy_m", "sz_m", "albedo"};
const std::vector<std::string> kPatchKeys = {"x_m", "y_m", "yaw_deg", "sx_m", "sy_m", "albedo"};
const std::vector<std::string> kPersonKeys = {"x_m", "y_m", "height_m"};
const std::vector<std::string> kPlatformKeys = {"x_m",    "y_m",  "yaw_deg", "sx_m",      "sy_m",         "sz_m",
                                                "albedo", "rows", "cols",    "spacing_m", "dot_radius_m", "dot_albedo"};

std::string Item(const std::string& list, size_t i) { return list + "[" + std::to_string(i) + "]"; }

ConeStyle ReadStyle(const StrictReader& r, const YAML::Node& map, const std::string& where) {
  const std::string s = r.String(map, where, "style", "road");
  if (s == "road") return ConeStyle::kRoad;
  if (s == "plain") return ConeStyle::kPlain;
  r.Fail(map["style"], FieldPath(where, "style"), "must be 'road' or 'plain', got '" + s + "'");
}

Eigen::Vector3d ReadColor(const StrictReader& r, const YAML::Node& map, const std::string& where, const char* key,
                          const Eigen::Vector3d& fallback) {
  const YAML::Node n = map[key];
  if (!n) return fallback;
  const std::string field = FieldPath(where, key);
  if (!n.IsSequence() || n.size() != 3) r.Fail(n, field, "must be [r, g, b]");
  Eigen::Vector3d c;
  for (int i = 0; i < 3; ++i) {
    try {
      c[i] = n[i].as<double>();
    } catch (const YAML::Exception&) {
      r.Fail(n, field, "components must be numbers");
    }
  }
  if (!((c.array() >= 0.0).all() && (c.array() <= 1.0).all())) r.Fail(n, field, "components must be in [0, 1]");
  return c;
}

int ReadInt(const StrictReader& r, const YAML::Node& map, const std::string& where, const char* key, int fallback) {
  const double v = r.Number(map, where, key, fallback);
  if (v != std::floor(v) || std::abs(v) > 1e6) r.Fail(map[key], FieldPath(where, key), "must be a whole number");
  return static_cast<int>(v);
}

void CheckList(const StrictReader& r, const YAML::Node& n, const std::string& key) {
  if (!n.IsSequence()) r.Fail(n, key, "must be a list of mappings like {x_m: 1.0, y_m: 0.0}");
}

ConeSpec ReadCone(const StrictReader& r, const YAML::Node& n, const std::string& where, const LayoutSchema& schema) {
  if (!schema.positions)
    for (const char* key : {"x_m", "y_m", "z_m", "sigma_m"})
      if (n.IsMap() && n[key]) r.Fail(n[key], FieldPath(where, key), schema.no_positions_why);
  r.CheckKeys(n, kConeKeys, where);
  const ConeStyle style = ReadStyle(r, n, where);
  const Eigen::Vector3d base(r.Number(n, where, "x_m", 0.0), r.Number(n, where, "y_m", 0.0),
                             r.Number(n, where, "z_m", 0.0));
  const double height_m =
      schema.height_required ? r.RequiredNumber(n, where, "height_m") : r.Number(n, where, "height_m", 0.71);
  ConeSpec cone = MakeCone(base, height_m, style);
  cone.tau = r.Number(n, where, "tau", cone.tau);
  if (!(cone.tau > 0.02 && cone.tau < 1.0)) r.Fail(n["tau"], FieldPath(where, "tau"), "must be in (0.02, 1)");
  cone.albedo = ReadColor(r, n, where, "albedo", cone.albedo);
  cone.base_plate_m = r.Number(n, where, "base_plate_m", cone.base_plate_m);
  if (const YAML::Node sigma = n["sigma_m"]) {  // a surveyed position's 1-sigma (surveyed_layout.h)
    const std::string field = FieldPath(where, "sigma_m");
    if (!sigma.IsSequence() || sigma.size() != 3) r.Fail(sigma, field, "must be [x, y, z] in metres");
    for (int i = 0; i < 3; ++i) {
      double v = NAN;
      try {
        v = sigma[i].as<double>();
      } catch (const YAML::Exception&) {
      }
      if (!(std::isfinite(v) && v >= 0.0)) r.Fail(sigma, field, "components must be finite and >= 0");
      cone.sigma_m[i] = v;
    }
  }
  if (!(cone.base_plate_m >= 0.0)) r.Fail(n["base_plate_m"], FieldPath(where, "base_plate_m"), "must be >= 0");
  if (const YAML::Node collars = n["collars"]) {
    const std::string field = FieldPath(where, "collars");
    if (!collars.IsSequence()) r.Fail(collars, field, "must be a list of [from, to] fractions of the height");
    cone.collars.clear();
    for (const YAML::Node& c : collars) {
      double a = NAN, b = NAN;
      if (c.IsSequence() && c.size() == 2) {
        try {
          a = c[0].as<double>(), b = c[1].as<double>();
        } catch (const YAML::Exception&) {
        }
      }
      if (!(a >= 0.0 && b <= 1.0 && a < b)) r.Fail(c, field, "each collar must be [from, to] with 0 <= from < to <= 1");
      cone.collars.emplace_back(a, b);
    }
  }
  return cone;
}

void ReadCones(const StrictReader& r, const YAML::Node& root, const LayoutSchema& schema, Layout* s) {
  if (const YAML::Node e = root["equilateral"]) {
    r.CheckKeys(e, kEquilateralKeys, "equilateral");
    const ConeStyle style = ReadStyle(r, e, "equilateral");
    const double side_m = r.Number(e, "equilateral", "side_m", 1.5);
    if (!(side_m > 0.0)) r.Fail(e["side_m"], "equilateral.side_m", "must be > 0");
    s->cones = EquilateralLayout(side_m, r.Number(e, "equilateral", "height_m", 0.71), style).cones;
  }
  if (const YAML::Node list = root["cones"]) {
    CheckList(r, list, "cones");
    for (size_t i = 0; i < list.size(); ++i) s->cones.push_back(ReadCone(r, list[i], Item("cones", i), schema));
  }
  const int n = static_cast<int>(s->cones.size());
  if (n == 0) r.Fail(root, "cones", "no cones: give 'cones:' or 'equilateral:'");
  if (n < LayoutLimits::kMinCones || n > LayoutLimits::kMaxCones) {
    r.Fail(root, "cones",
           "the " + schema.what + " has " + std::to_string(n) + " cones; " + std::to_string(LayoutLimits::kMinCones) +
               " to " + std::to_string(LayoutLimits::kMaxCones) + " are supported");
  }
  // Where each cone came from, for the messages below: the equilateral cones come first.
  const size_t first_listed = root["equilateral"] ? 3 : 0;
  auto where = [&](size_t i) {
    return i < first_listed
               ? std::make_pair(root["equilateral"], std::string("equilateral"))
               : std::make_pair(YAML::Node(root["cones"][i - first_listed]), Item("cones", i - first_listed));
  };
  for (size_t i = 0; i < s->cones.size(); ++i) {
    const double h = s->cones[i].height_m;
    if (h < LayoutLimits::kMinHeightM - 1e-9 || h > LayoutLimits::kMaxHeightM + 1e-9) {
      std::ostringstream m;
      m << h << " is outside [" << LayoutLimits::kMinHeightM << ", " << LayoutLimits::kMaxHeightM
        << "] m (4\" to 36\" cones)";
      const auto w = where(i);
      r.Fail(w.first["height_m"] ? w.first["height_m"] : w.first, w.second + ".height_m", m.str());
    }
    for (size_t j = 0; j < i && schema.positions; ++j) {
      if ((s->cones[i].base_m - s->cones[j].base_m).norm() < 1e-6 && std::abs(h - s->cones[j].height_m) < 1e-6)
        r.Fail(where(i).first, where(i).second,
               "is identical to " + where(j).second + " (cone " + std::to_string(j) + ")");
    }
  }
}

void ReadScenery(const StrictReader& r, const YAML::Node& root, Layout* s) {
  if (const YAML::Node list = root["boxes"]) {
    CheckList(r, list, "boxes");
    for (size_t i = 0; i < list.size(); ++i) {
      const YAML::Node& b = list[i];
      const std::string w = Item("boxes", i);
      r.CheckKeys(b, kBoxKeys, w);
      BoxSpec box;
      box.size_m =
          Eigen::Vector3d(r.Number(b, w, "sx_m", 0.4), r.Number(b, w, "sy_m", 0.3), r.Number(b, w, "sz_m", 0.3));
      box.center_m = Eigen::Vector3d(r.Number(b, w, "x_m", 0.0), r.Number(b, w, "y_m", 0.0), 0.5 * box.size_m.z());
      box.yaw_rad = r.Number(b, w, "yaw_deg", 0.0) * kPi / 180.0;
      box.albedo = ReadColor(r, b, w, "albedo", box.albedo);
      if ((box.size_m.array() <= 0.0).any()) r.Fail(b, w, "sizes sx_m, sy_m, sz_m must be positive");
      s->boxes.push_back(box);
    }
  }
  if (const YAML::Node list = root["patches"]) {
    CheckList(r, list, "patches");
    for (size_t i = 0; i < list.size(); ++i) {
      const YAML::Node& p = list[i];
      const std::string w = Item("patches", i);
      r.CheckKeys(p, kPatchKeys, w);
      PatchSpec patch;
      patch.center_m = Eigen::Vector2d(r.Number(p, w, "x_m", 0.0), r.Number(p, w, "y_m", 0.0));
      patch.size_m = Eigen::Vector2d(r.Number(p, w, "sx_m", 0.5), r.Number(p, w, "sy_m", 0.5));
      patch.yaw_rad = r.Number(p, w, "yaw_deg", 0.0) * kPi / 180.0;
      patch.albedo = ReadColor(r, p, w, "albedo", patch.albedo);
      if ((patch.size_m.array() <= 0.0).any()) r.Fail(p, w, "sizes sx_m, sy_m must be positive");
      s->patches.push_back(patch);
    }
  }
  if (const YAML::Node list = root["people"]) {
    CheckList(r, list, "people");
    for (size_t i = 0; i < list.size(); ++i) {
      const YAML::Node& p = list[i];
      const std::string w = Item("people", i);
      r.CheckKeys(p, kPersonKeys, w);
      PersonSpec person;
      person.position_m = Eigen::Vector2d(r.Number(p, w, "x_m", 0.0), r.Number(p, w, "y_m", 0.0));
      person.height_m = r.Number(p, w, "height_m", person.height_m);
      if (!(person.height_m > 0.0)) r.Fail(p["height_m"], FieldPath(w, "height_m"), "must be > 0");
      s->people.push_back(person);
    }
  }
  if (const YAML::Node list = root["platforms"]) {
    CheckList(r, list, "platforms");
    for (size_t i = 0; i < list.size(); ++i) {
      const YAML::Node& p = list[i];
      const std::string w = Item("platforms", i);
      r.CheckKeys(p, kPlatformKeys, w);
      PlatformSpec pl;
      pl.center_m = Eigen::Vector2d(r.Number(p, w, "x_m", 0.0), r.Number(p, w, "y_m", 0.0));
      pl.yaw_rad = r.Number(p, w, "yaw_deg", 0.0) * kPi / 180.0;
      pl.size_m = Eigen::Vector3d(r.Number(p, w, "sx_m", pl.size_m.x()), r.Number(p, w, "sy_m", pl.size_m.y()),
                                  r.Number(p, w, "sz_m", pl.size_m.z()));
      pl.albedo = ReadColor(r, p, w, "albedo", pl.albedo);
      pl.rows = ReadInt(r, p, w, "rows", pl.rows);
      pl.cols = ReadInt(r, p, w, "cols", pl.cols);
      pl.spacing_m = r.Number(p, w, "spacing_m", pl.spacing_m);
      pl.dot_radius_m = r.Number(p, w, "dot_radius_m", pl.dot_radius_m);
      pl.dot_albedo = ReadColor(r, p, w, "dot_albedo", pl.dot_albedo);
      if ((pl.size_m.array() <= 0.0).any()) r.Fail(p, w, "sizes sx_m, sy_m, sz_m must be positive");
      if (pl.rows < 1 || pl.cols < 1) r.Fail(p, w, "rows and cols must be at least 1");
      if (!(pl.dot_radius_m > 0.0) || !(pl.spacing_m > 2.0 * pl.dot_radius_m))
        r.Fail(p, w, "need 0 < dot_radius_m < spacing_m / 2");
      if ((pl.cols - 1) * pl.spacing_m + 2 * pl.dot_radius_m > pl.size_m.x() ||
          (pl.rows - 1) * pl.spacing_m + 2 * pl.dot_radius_m > pl.size_m.y())
        r.Fail(p, w, "the dot grid does not fit on the board");
      s->platforms.push_back(pl);
    }
  }
  if (root["ground"]) {
    const std::string g = r.String(root, "", "ground", "asphalt");
    if (g == "asphalt")
      s->ground = GroundStyle::kAsphalt;
    else if (g == "grass")
      s->ground = GroundStyle::kGrass;
    else if (g == "concrete")
      s->ground = GroundStyle::kConcrete;
    else
      r.Fail(root["ground"], "ground", "must be asphalt, grass or concrete, got '" + g + "'");
  }
}

}  // namespace

Layout ParseLayoutRoot(const YAML::Node& root, const std::string& source, const LayoutSchema& schema) {
  const StrictReader r(source);
  if (!root || root.IsNull())
    throw FileError(source + ": empty; a " + schema.what + " needs 'cones:'" +
                    (schema.positions ? " or 'equilateral:'" : ""));
  std::vector<std::string> keys = schema.positions ? kTopKeys : std::vector<std::string>{"cones"};
  keys.insert(keys.end(), schema.extra_top_keys.begin(), schema.extra_top_keys.end());
  r.CheckKeys(root, keys, "");
  Layout s;
  ReadCones(r, root, schema, &s);
  if (schema.positions) ReadScenery(r, root, &s);
  return s;
}

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

Eigen::Vector3d Layout::ConeCentroid() const {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& cone : cones) c += cone.base_m;
  return cones.empty() ? c : Eigen::Vector3d(c / static_cast<double>(cones.size()));
}

std::array<Eigen::Vector3d, 3> CorrectedModelPoints(const Eigen::Vector3d& base_m, double height_m, double tau,
                                                    const Eigen::Vector3d& eye) {
  Eigen::Vector3d toward = eye - base_m;
  toward.z() = 0.0;  // COP' in the base plane (3.16)
  const double n = toward.norm();
  toward = n > 1e-9 ? Eigen::Vector3d(toward / n) : Eigen::Vector3d::Zero();  // (3.17)
  const double r = tau * height_m;                                            // (3.13)
  const Eigen::Vector3d up(0, 0, height_m);
  return {base_m + up, base_m + 0.5 * up + 0.5 * r * toward, base_m + r * toward};  // (3.18)
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

Layout EquilateralLayout(double side_m, double height_m, ConeStyle style) {
  Layout s;
  const double circumradius = side_m / std::sqrt(3.0);
  for (int i = 0; i < 3; ++i) {
    const double a = 2.0 * kPi * i / 3.0;
    s.cones.push_back(
        MakeCone(Eigen::Vector3d(circumradius * std::cos(a), circumradius * std::sin(a), 0.0), height_m, style));
  }
  return s;
}

Layout DefaultLayout() { return EquilateralLayout(1.5, 0.71, ConeStyle::kRoad); }

Layout ParseLayout(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw FileError(source + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML: " + e.msg);
  }
  return ParseLayoutRoot(root, source, LayoutSchema());
}

Layout LoadLayoutFile(const std::string& path) { return ParseLayoutRoot(LoadYamlFile(path), path, LayoutSchema()); }

std::vector<Eigen::Vector3d> LoadConeSigmas(const std::string& path) {
  std::vector<Eigen::Vector3d> out;
  for (const ConeSpec& c : LoadLayoutFile(path).cones) out.push_back(c.sigma_m);
  return out;
}

std::string ConesYaml(const std::vector<ConeSpec>& cones, const std::vector<Eigen::Vector3d>& sigmas_m) {
  std::ostringstream y;
  y.setf(std::ios::fixed);
  y << "cones:\n";
  for (size_t i = 0; i < cones.size(); ++i) {
    const ConeSpec& c = cones[i];
    y.precision(4);
    y << "  - {x_m: " << c.base_m.x() << ", y_m: " << c.base_m.y() << ", z_m: " << c.base_m.z()
      << ", height_m: " << c.height_m << ", style: " << (c.style == ConeStyle::kRoad ? "road" : "plain");
    y.precision(6);
    if (std::abs(c.tau - ConeSpec().tau) > 1e-9) y << ", tau: " << c.tau;
    if (i < sigmas_m.size() && !sigmas_m[i].array().isNaN().any()) {
      y.precision(4);
      y << ", sigma_m: [" << sigmas_m[i].x() << ", " << sigmas_m[i].y() << ", " << sigmas_m[i].z() << "]";
    }
    y << "}\n";
  }
  return y.str();
}

}  // namespace rig_model
