#include "ar_overlay/core/scene.h"

#include <cmath>
#include <set>
#include <stdexcept>

#include "rig_model/strict_yaml.h"

namespace ar_overlay {
namespace {

const std::vector<std::string> kModelKeys = {"name",   "file",  "scale", "xyz",  "rpy",
                                             "parent", "joint", "alpha", "color"};

Eigen::Vector3d Vec3(const rig_model::StrictReader& r, const YAML::Node& map, const std::string& where,
                     const std::string& key, const Eigen::Vector3d& fallback) {
  const YAML::Node n = map[key];
  if (!n) return fallback;
  const std::string field = rig_model::FieldPath(where, key);
  if (!n.IsSequence() || n.size() != 3) r.Fail(n, field, "must be a list of three numbers");
  Eigen::Vector3d v;
  for (size_t i = 0; i < 3; ++i) {
    try {
      v(i) = n[i].as<double>();
    } catch (const YAML::Exception&) {
      r.Fail(n, field, "must be a list of three numbers");
    }
  }
  if (!v.allFinite()) r.Fail(n, field, "is not finite");
  return v;
}

ModelSpec ParseModel(const rig_model::StrictReader& r, const YAML::Node& n, const std::string& where,
                     const std::string& folder, const std::set<std::string>& earlier) {
  r.CheckKeys(n, kModelKeys, where);
  ModelSpec s;
  s.name = r.String(n, where, "name", "");
  if (s.name.empty()) r.Fail(n, where + ".name", "a model needs a name");
  if (earlier.count(s.name)) r.Fail(n["name"], where + ".name", "'" + s.name + "' is used twice");
  if (!n["file"]) r.Fail(n, where + ".file", "is missing");
  s.file = r.String(n, where, "file", "");
  if (!s.file.empty() && s.file[0] != '/') s.file = folder + s.file;
  s.scale = r.Number(n, where, "scale", 1.0);
  if (!(s.scale > 0)) r.Fail(n["scale"], where + ".scale", "must be > 0");
  const Eigen::Vector3d xyz = Vec3(r, n, where, "xyz", Eigen::Vector3d::Zero());
  const Eigen::Vector3d rpy = Vec3(r, n, where, "rpy", Eigen::Vector3d::Zero());
  s.T_parent_origin.translation() = xyz;
  s.T_parent_origin.linear() =
      (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
          .toRotationMatrix();  // fixed-axis roll, pitch, yaw (REP-103)
  s.parent = r.String(n, where, "parent", "");
  if (!s.parent.empty() && !earlier.count(s.parent))
    r.Fail(n["parent"], where + ".parent", "'" + s.parent + "' is not listed before it");
  if (const YAML::Node j = n["joint"]) {
    const std::string jw = where + ".joint";
    r.CheckKeys(j, {"name", "axis"}, jw);
    s.joint_name = r.String(j, jw, "name", "");
    if (s.joint_name.empty()) r.Fail(j, jw + ".name", "a joint needs a name");
    s.joint_axis = Vec3(r, j, jw, "axis", Eigen::Vector3d::UnitZ());
    if (s.joint_axis.norm() < 1e-9) r.Fail(j, jw + ".axis", "is zero");
    s.joint_axis.normalize();
  }
  s.alpha = r.Number(n, where, "alpha", 1.0);
  if (!(s.alpha >= 0 && s.alpha <= 1)) r.Fail(n["alpha"], where + ".alpha", "must be in [0, 1]");
  if (n["color"]) {
    s.has_color = true;
    s.color = Vec3(r, n, where, "color", Eigen::Vector3d::Ones()).cast<float>();
  }
  return s;
}

}  // namespace

std::vector<ModelSpec> LoadSceneYaml(const std::string& path) {
  const std::string folder = path.substr(0, path.find_last_of('/') + 1);
  const rig_model::StrictReader r(path);
  const YAML::Node root = rig_model::LoadYamlFile(path);
  r.CheckKeys(root, {"models"}, "");
  const YAML::Node models = root["models"];
  if (!models || !models.IsSequence()) r.Fail(root, "models", "must be a list of models");
  std::vector<ModelSpec> specs;
  std::set<std::string> names;
  for (size_t i = 0; i < models.size(); ++i) {
    specs.push_back(ParseModel(r, models[i], "models[" + std::to_string(i) + "]", folder, names));
    names.insert(specs.back().name);
  }
  return specs;
}

std::vector<Eigen::Isometry3d> ModelPoses(const std::vector<ModelSpec>& specs,
                                          const std::map<std::string, double>& joint_rad) {
  std::vector<Eigen::Isometry3d> T_cones_model;
  std::map<std::string, size_t> index;
  for (const ModelSpec& s : specs) {
    Eigen::Isometry3d T = s.T_parent_origin;
    if (!s.parent.empty()) {
      const auto it = index.find(s.parent);
      if (it == index.end()) throw std::invalid_argument("ModelPoses: '" + s.name + "' listed before its parent");
      T = T_cones_model[it->second] * T;
    }
    if (!s.joint_name.empty()) {
      const auto q = joint_rad.find(s.joint_name);
      if (q != joint_rad.end() && std::isfinite(q->second)) T.rotate(Eigen::AngleAxisd(q->second, s.joint_axis));
    }
    index[s.name] = T_cones_model.size();
    T_cones_model.push_back(T);
  }
  return T_cones_model;
}

}  // namespace ar_overlay
