// Which models to draw and where: a YAML list placing model files in the
// `cones` frame, optionally chained as links with revolute joints (the arm
// follows sensor_msgs/JointState through SetJointPositions).
//
//   models:
//     - name: peaks             # unique
//       file: peaks.ply         # relative to the YAML's folder, or absolute
//       scale: 0.1              # uniform, applied to this model's mesh only
//       xyz: [0, 0, 0.3]        # origin in the parent (or cones), metres
//       rpy: [0, 0, 0]          # fixed-axis roll, pitch, yaw, radians
//       parent: ""              # another model's name: a link in a chain
//       joint: {name: joint_a1, axis: [0, 0, 1]}   # revolute, after xyz/rpy
//       alpha: 1.0              # opacity in [0, 1]
//       color: [1, 0, 0]        # optional: replaces the file's colours
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <string>
#include <vector>

namespace ar_overlay {

struct ModelSpec {
  std::string name;
  std::string file;  // resolved to an absolute path by LoadSceneYaml
  double scale = 1.0;
  Eigen::Isometry3d T_parent_origin = Eigen::Isometry3d::Identity();
  std::string parent;  // "" is the cones frame
  std::string joint_name;
  Eigen::Vector3d joint_axis = Eigen::Vector3d::UnitZ();
  double alpha = 1.0;
  bool has_color = false;
  Eigen::Vector3f color = Eigen::Vector3f::Ones();
};

// Parses and validates the YAML (unique names, parents that exist and come
// first, scale > 0, alpha in [0, 1], non-zero joint axes). Throws
// std::runtime_error naming the file and the bad entry.
std::vector<ModelSpec> LoadSceneYaml(const std::string& path);

// T_cones_model for every spec (listed parents first), joints at `joint_rad`
// (missing joints at 0). Scale is not included.
std::vector<Eigen::Isometry3d> ModelPoses(const std::vector<ModelSpec>& specs,
                                          const std::map<std::string, double>& joint_rad);

}  // namespace ar_overlay
