#include "ar_overlay/core/scene.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>
#include <stdexcept>

namespace ar_overlay {
namespace {

Eigen::Vector3d Vec3(const YAML::Node& n, const Eigen::Vector3d& fallback, const std::string& what) {
  if (!n) return fallback;
  if (!n.IsSequence() || n.size() != 3) throw std::runtime_error(what + " must be a list of three numbers");
  Eigen::Vector3d v(n[0].as<double>(), n[1].as<double>(), n[2].as<double>());
  if (!v.allFinite()) throw std::runtime_error(what + " is not finite");
  return v;
}

ModelSpec ParseModel(const YAML::Node& n, const std::string& folder, const std::set<std::string>& earlier) {
  ModelSpec s;
  s.name = n["name"] ? n["name"].as<std::string>() : "";
  if (s.name.empty()) throw std::runtime_error("a model has no name");
  const std::string where = "model '" + s.name + "': ";
  if (earlier.count(s.name)) throw std::runtime_error(where + "name used twice");
  if (!n["file"]) throw std::runtime_error(where + "no file");
  s.file = n["file"].as<std::string>();
  if (!s.file.empty() && s.file[0] != '/') s.file = folder + s.file;
  s.scale = n["scale"] ? n["scale"].as<double>() : 1.0;
  if (!(s.scale > 0) || !std::isfinite(s.scale)) throw std::runtime_error(where + "scale must be > 0");
  const Eigen::Vector3d xyz = Vec3(n["xyz"], Eigen::Vector3d::Zero(), where + "xyz");
  const Eigen::Vector3d rpy = Vec3(n["rpy"], Eigen::Vector3d::Zero(), where + "rpy");
  s.T_parent_origin.translation() = xyz;
  s.T_parent_origin.linear() =
      (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
          .toRotationMatrix();  // fixed-axis roll, pitch, yaw (REP-103)
  s.parent = n["parent"] ? n["parent"].as<std::string>() : "";
  if (!s.parent.empty() && !earlier.count(s.parent))
    throw std::runtime_error(where + "parent '" + s.parent + "' is not listed before it");
  if (const YAML::Node j = n["joint"]) {
    s.joint_name = j["name"] ? j["name"].as<std::string>() : "";
    if (s.joint_name.empty()) throw std::runtime_error(where + "joint has no name");
    s.joint_axis = Vec3(j["axis"], Eigen::Vector3d::UnitZ(), where + "joint axis");
    if (s.joint_axis.norm() < 1e-9) throw std::runtime_error(where + "joint axis is zero");
    s.joint_axis.normalize();
  }
  s.alpha = n["alpha"] ? n["alpha"].as<double>() : 1.0;
  if (!(s.alpha >= 0 && s.alpha <= 1)) throw std::runtime_error(where + "alpha must be in [0, 1]");
  if (n["color"]) {
    s.has_color = true;
    s.color = Vec3(n["color"], Eigen::Vector3d::Ones(), where + "color").cast<float>();
  }
  return s;
}

}  // namespace

std::vector<ModelSpec> LoadSceneYaml(const std::string& path) {
  const std::string folder = path.substr(0, path.find_last_of('/') + 1);
  std::vector<ModelSpec> specs;
  try {
    const YAML::Node root = YAML::LoadFile(path);
    const YAML::Node models = root["models"];
    if (!models || !models.IsSequence()) throw std::runtime_error("no 'models' list");
    std::set<std::string> names;
    for (const YAML::Node& n : models) {
      specs.push_back(ParseModel(n, folder, names));
      names.insert(specs.back().name);
    }
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(path + ": " + e.what());
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
