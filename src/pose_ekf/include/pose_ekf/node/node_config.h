// Parameters of the pose_ekf nodelet: frames, output rate and the core's EkfConfig, described once by
// Params(), the table that maps NodeConfig <-> ROS parameters <-> dynamic_reconfigure <-> YAML.
#pragma once

#include <string>
#include <vector>

#include "pose_ekf/core/cone_measurement.h"
#include "pose_ekf/core/config.h"
#include "rig_model/param_table.h"

namespace ros {
class NodeHandle;
}

namespace pose_ekf {

struct NodeConfig {
  std::string cones_frame = "cones";            // fixed frame {M}, z up
  std::string camera_frame = "camera_optical";  // {C}
  bool publish_tf = true;
  double output_rate_hz = 0.0;  // > 0: also publish the pose predicted to now at this rate (thesis: 40 Hz)
  double imu_expected_rate_hz = 100.0;
  double camera_expected_rate_hz = 30.0;
  double tf_timeout_s = 0.05;  // the first lookup of the camera-IMU static transform waits this long
  // The parameters behind ekf.accel_mode and ekf.quat_integration (ApplyModes): the GUI switch
  // use_accel, the model it switches on (an AccelMode), and a QuatIntegration, as the table's ints.
  bool use_accel = true;
  int accel_mode = static_cast<int>(AccelMode::kPositionAndOrientation);
  int quat_integration = static_cast<int>(QuatIntegration::kFirstOrder);
  int camera_update = static_cast<int>(CameraUpdate::kPose);  // ApplyModes sets ekf.camera_update
  // The cone layout, the file cone_tracker loads (its ~layout_file): rig_model's schema and parser.
  // Needed for cone_tracker/observations; without it only camera poses are used.
  std::string layout_file;
  std::vector<ConeGeometry> layout_cones;  // read from layout_file by LoadConfig (not a parameter)
  // ~config_file: a note set by pose_ekf.launch naming the YAML it loaded, so that errors name the file.
  std::string config_file;
  EkfConfig ekf;
};

// The one parameter table: every name under ~, in the YAML files and in cfg/PoseEkf.cfg, with the unit
// in the name. Enums as names or indices: accel_mode off|orientation|position_orientation,
// quat_integration first_order|exact.
const rig_model::ParamTable<NodeConfig>& Params();
// Every parameter name (Params().Names()).
std::vector<std::string> ParamNames();

// Sets ekf.accel_mode (use_accel ? accel_mode : off), ekf.quat_integration and ekf.camera_update from
// the table's fields.
void ApplyModes(NodeConfig* config);
// ApplyModes, then the range checks; throws std::invalid_argument naming the parameter.
void ValidateConfig(NodeConfig* config);

// From the private namespace (rig_model::LoadParams: type-checked; a parameter there that the table
// does not know is refused, "parameter ~sigma_gyr_rad_s is unknown (did you mean ~sigma_gyro_rad_s?)"),
// then ValidateConfig. When ~config_file is set its keys are checked line by line first and errors
// name it. Throws std::invalid_argument.
NodeConfig LoadConfig(const ros::NodeHandle& private_nh);
// The same table from a YAML file of config/pose_ekf.yaml's form (ekf_replay --config); an unknown key
// or a wrong type is refused with the file, its line and (for a typo) the nearest known key.
NodeConfig LoadConfigFile(const std::string& yaml_path);
// Reads config->layout_file (if set) into config->layout_cones; both loaders call it. Throws
// std::invalid_argument with rig_model's message naming the file, line and field.
void LoadLayout(NodeConfig* config);

}  // namespace pose_ekf
