#include "pose_ekf/node/node_config.h"

#include <ros/node_handle.h>
#include <yaml-cpp/yaml.h>

#include <stdexcept>

#include "rig_model/layout.h"
#include "rig_model/ros/param_table_ros.h"
#include "rig_model/strict_yaml.h"

namespace pose_ekf {
namespace {

using Table = rig_model::ParamTable<NodeConfig>;

const char kConfigFileParam[] = "config_file";

// The YAML file's mapping (a file of comments only: an empty one, all defaults). Throws FileError.
YAML::Node MappingOf(const std::string& yaml_path) {
  YAML::Node root = rig_model::LoadYamlFile(yaml_path);
  return root.IsNull() ? YAML::Node(YAML::NodeType::Map) : root;
}

// Reads the YAML file through the table: "file:line: unknown key 'x' (did you mean 'y'?)" or
// "file:line: x: must be a number". Throws std::invalid_argument.
void ReadFile(const std::string& yaml_path, NodeConfig* config) {
  try {
    Params().FromYaml(MappingOf(yaml_path), rig_model::StrictReader(yaml_path), "", config);
  } catch (const rig_model::FileError& e) {
    throw std::invalid_argument(e.what());
  }
}

// ~config_file alone, through the table (type-checked), before the rest: its errors name the file.
std::string ConfigFileNote(const ros::NodeHandle& pnh) {
  NodeConfig c;
  try {
    rig_model::ParamValue value;
    if (rig_model::FetchParam(pnh, kConfigFileParam, &value)) Params().Set(&c, kConfigFileParam, value);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("parameter ~") + e.what());
  }
  return c.config_file;
}

}  // namespace

const Table& Params() {
  // clang-format off
  static const Table table = Table()
      .Add("cones_frame", [](NodeConfig& c) -> std::string& { return c.cones_frame; })
      .Add("camera_frame", [](NodeConfig& c) -> std::string& { return c.camera_frame; })
      .Add("publish_tf", [](NodeConfig& c) -> bool& { return c.publish_tf; })
      .Add("output_rate_hz", [](NodeConfig& c) -> double& { return c.output_rate_hz; })
      .Add("imu_expected_rate_hz", [](NodeConfig& c) -> double& { return c.imu_expected_rate_hz; })
      .Add("camera_expected_rate_hz", [](NodeConfig& c) -> double& { return c.camera_expected_rate_hz; })
      .Add("tf_timeout_s", [](NodeConfig& c) -> double& { return c.tf_timeout_s; })
      .Add("config_file", [](NodeConfig& c) -> std::string& { return c.config_file; })
      // Process noise (5.23) and IMU measurement noise (section 5.6).
      .Add("sigma_q_per_sqrt_s", [](NodeConfig& c) -> double& { return c.ekf.sigma_q_per_sqrt_s; })
      .Add("sigma_omega_rad_s_per_sqrt_s", [](NodeConfig& c) -> double& { return c.ekf.sigma_omega_rad_s_per_sqrt_s; })
      .Add("sigma_p_m_per_sqrt_s", [](NodeConfig& c) -> double& { return c.ekf.sigma_p_m_per_sqrt_s; })
      .Add("sigma_v_m_s_per_sqrt_s", [](NodeConfig& c) -> double& { return c.ekf.sigma_v_m_s_per_sqrt_s; })
      .Add("sigma_a_m_s2_per_sqrt_s", [](NodeConfig& c) -> double& { return c.ekf.sigma_a_m_s2_per_sqrt_s; })
      .Add("sigma_gyro_bias_rad_s_per_sqrt_s",
           [](NodeConfig& c) -> double& { return c.ekf.sigma_gyro_bias_rad_s_per_sqrt_s; })
      .Add("sigma_gyro_rad_s", [](NodeConfig& c) -> double& { return c.ekf.sigma_gyro_rad_s; })
      .Add("sigma_accel_m_s2", [](NodeConfig& c) -> double& { return c.ekf.sigma_accel_m_s2; })
      .Add("use_message_imu_covariance", [](NodeConfig& c) -> bool& { return c.ekf.use_message_imu_covariance; })
      // Updates (the thesis GUI's switches); ApplyModes turns use_accel and accel_mode into ekf.accel_mode.
      .Add("use_camera", [](NodeConfig& c) -> bool& { return c.ekf.use_camera; })
      .Add("use_gyro", [](NodeConfig& c) -> bool& { return c.ekf.use_gyro; })
      .Add("gyro_is_interval_mean", [](NodeConfig& c) -> bool& { return c.ekf.gyro_is_interval_mean; })
      .Add("omega_walk_at_gyro", [](NodeConfig& c) -> bool& { return c.ekf.omega_walk_at_gyro; })
      .Add("gyro_is_centred_interval_mean",
           [](NodeConfig& c) -> bool& { return c.ekf.gyro_is_centred_interval_mean; })
      .AddEnum("accel_mode", [](NodeConfig& c) -> int& { return c.accel_mode; },
               {"off", "orientation", "position_orientation"})  // AccelMode's order
      .AddEnum("quat_integration", [](NodeConfig& c) -> int& { return c.quat_integration; },
               {"first_order", "exact"})  // QuatIntegration's order
      .Add("use_accel", [](NodeConfig& c) -> bool& { return c.use_accel; })
      .Add("gravity_m_s2", [](NodeConfig& c) -> double& { return c.ekf.gravity_m_s2; })
      .Add("accel_gate_m_s2", [](NodeConfig& c) -> double& { return c.ekf.accel_gate_m_s2; })
      .Add("camera_gate_chi2", [](NodeConfig& c) -> double& { return c.ekf.camera_gate_chi2; })
      .Add("reinit_after_rejections", [](NodeConfig& c) -> int& { return c.ekf.reinit_after_rejections; })
      // Tightly coupled camera updates from cone_tracker/observations (cone_measurement.h).
      .AddEnum("camera_update", [](NodeConfig& c) -> int& { return c.camera_update; },
               {"cones", "pose"})  // CameraUpdate's order
      .Add("cone_gate_probability", [](NodeConfig& c) -> double& { return c.ekf.cone_gate_probability; })
      .Add("cone_joint_probability", [](NodeConfig& c) -> double& { return c.ekf.cone_joint_probability; })
      .Add("reacquire_sigma_p_m", [](NodeConfig& c) -> double& { return c.ekf.reacquire_sigma_p_m; })
      .Add("reacquire_min_cones", [](NodeConfig& c) -> int& { return c.ekf.reacquire_min_cones; })
      .Add("cone_ambiguity_margin", [](NodeConfig& c) -> double& { return c.ekf.cone_ambiguity_margin; })
      .Add("cone_ambiguity_iterations", [](NodeConfig& c) -> int& { return c.ekf.cone_ambiguity_iterations; })
      .Add("cone_miss_cost", [](NodeConfig& c) -> double& { return c.ekf.cone_miss_cost; })
      .Add("cone_unexplained_cost", [](NodeConfig& c) -> double& { return c.ekf.cone_unexplained_cost; })
      .Add("cone_update_iterations", [](NodeConfig& c) -> int& { return c.ekf.cone_update_iterations; })
      .Add("cone_repeat_px", [](NodeConfig& c) -> double& { return c.ekf.cone_repeat_px; })
      .Add("cone_repeat_max_s", [](NodeConfig& c) -> double& { return c.ekf.cone_repeat_max_s; })
      .Add("cone_repeat_sigma_v_m_s", [](NodeConfig& c) -> double& { return c.ekf.cone_repeat_sigma_v_m_s; })
      .Add("cone_repeat_sigma_omega_rad_s",
           [](NodeConfig& c) -> double& { return c.ekf.cone_repeat_sigma_omega_rad_s; })
      .Add("layout_file", [](NodeConfig& c) -> std::string& { return c.layout_file; })
      // Options beyond the thesis, initial uncertainty and the measurement buffer (section 6.3).
      .Add("estimate_gyro_bias", [](NodeConfig& c) -> bool& { return c.ekf.estimate_gyro_bias; })
      .Add("joseph_update", [](NodeConfig& c) -> bool& { return c.ekf.joseph_update; })
      .Add("init_sigma_omega_rad_s", [](NodeConfig& c) -> double& { return c.ekf.init_sigma_omega_rad_s; })
      .Add("init_sigma_v_m_s", [](NodeConfig& c) -> double& { return c.ekf.init_sigma_v_m_s; })
      .Add("init_sigma_a_m_s2", [](NodeConfig& c) -> double& { return c.ekf.init_sigma_a_m_s2; })
      .Add("init_sigma_gyro_bias_rad_s", [](NodeConfig& c) -> double& { return c.ekf.init_sigma_gyro_bias_rad_s; })
      .Add("init_from_gravity", [](NodeConfig& c) -> bool& { return c.ekf.init_from_gravity; })
      .Add("init_sigma_tilt_rad", [](NodeConfig& c) -> double& { return c.ekf.init_sigma_tilt_rad; })
      .Add("init_sigma_heading_rad", [](NodeConfig& c) -> double& { return c.ekf.init_sigma_heading_rad; })
      .Add("init_sigma_p_m", [](NodeConfig& c) -> double& { return c.ekf.init_sigma_p_m; })
      .Add("max_delay_s", [](NodeConfig& c) -> double& { return c.ekf.max_delay_s; })
      .Add("time_jump_reset_s", [](NodeConfig& c) -> double& { return c.ekf.time_jump_reset_s; })
      .Add("max_predict_step_s", [](NodeConfig& c) -> double& { return c.ekf.max_predict_step_s; })
      // The lever arm, the accelerometer bias and the motion model in camera outages.
      .Add("model_lever_arm", [](NodeConfig& c) -> bool& { return c.ekf.model_lever_arm; })
      .Add("alpha_from_gyro", [](NodeConfig& c) -> bool& { return c.ekf.alpha_from_gyro; })
      .Add("sigma_angular_accel_rad_s2", [](NodeConfig& c) -> double& { return c.ekf.sigma_angular_accel_rad_s2; })
      .Add("estimate_accel_bias", [](NodeConfig& c) -> bool& { return c.ekf.estimate_accel_bias; })
      .Add("sigma_accel_bias_m_s2_per_sqrt_s",
           [](NodeConfig& c) -> double& { return c.ekf.sigma_accel_bias_m_s2_per_sqrt_s; })
      .Add("init_sigma_accel_bias_m_s2", [](NodeConfig& c) -> double& { return c.ekf.init_sigma_accel_bias_m_s2; })
      .Add("velocity_time_constant_s", [](NodeConfig& c) -> double& { return c.ekf.velocity_time_constant_s; })
      .Add("accel_time_constant_s", [](NodeConfig& c) -> double& { return c.ekf.accel_time_constant_s; });
  // clang-format on
  return table;
}

std::vector<std::string> ParamNames() { return Params().Names(); }

void ApplyModes(NodeConfig* c) {
  c->ekf.accel_mode = c->use_accel ? static_cast<AccelMode>(c->accel_mode) : AccelMode::kOff;
  c->ekf.quat_integration = static_cast<QuatIntegration>(c->quat_integration);
  c->ekf.camera_update = static_cast<CameraUpdate>(c->camera_update);
}

void ValidateConfig(NodeConfig* config) {
  ApplyModes(config);
  const NodeConfig& c = *config;
  if (c.cones_frame.empty()) throw std::invalid_argument("cones_frame must not be empty");
  if (c.camera_frame.empty()) throw std::invalid_argument("camera_frame must not be empty");
  if (!(c.output_rate_hz >= 0.0)) throw std::invalid_argument("output_rate_hz must be >= 0");
  if (!(c.imu_expected_rate_hz > 0.0)) throw std::invalid_argument("imu_expected_rate_hz must be > 0");
  if (!(c.camera_expected_rate_hz > 0.0)) throw std::invalid_argument("camera_expected_rate_hz must be > 0");
  if (!(c.tf_timeout_s >= 0.0)) throw std::invalid_argument("tf_timeout_s must be >= 0");
  // The ranges of PoseEkf.cfg, so that dynamic_reconfigure never clamps a loaded value.
  const int reinit = c.ekf.reinit_after_rejections;  // the table has refused a non-integer already
  if (reinit < 0 || reinit > 1000) {
    throw std::invalid_argument(
        "reinit_after_rejections must be a whole number in [0, 1000], 0 never re-initialises (got " +
        std::to_string(reinit) + ")");
  }
  if (c.ekf.camera_gate_chi2 > 1e6) {
    throw std::invalid_argument("camera_gate_chi2 must be <= 1e6, 0 disables the gate (got " +
                                std::to_string(c.ekf.camera_gate_chi2) + ")");
  }
  const std::string err = c.ekf.Validate();
  if (!err.empty()) throw std::invalid_argument(err);
}

NodeConfig LoadConfig(const ros::NodeHandle& private_nh) {
  const std::string file = ConfigFileNote(private_nh);
  if (!file.empty()) {
    NodeConfig from_file;
    ReadFile(file, &from_file);  // a misspelt key or a wrong type, with its line
  }
  try {
    NodeConfig c;
    rig_model::LoadParams(private_nh, Params(), &c);
    ValidateConfig(&c);
    LoadLayout(&c);
    return c;
  } catch (const std::invalid_argument& e) {
    if (file.empty()) throw;
    throw std::invalid_argument(std::string(e.what()) + " (parameters loaded from " + file + ")");
  }
}

NodeConfig LoadConfigFile(const std::string& yaml_path) {
  NodeConfig c;
  ReadFile(yaml_path, &c);
  try {
    ValidateConfig(&c);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(yaml_path + ": " + e.what());
  }
  LoadLayout(&c);
  return c;
}

void LoadLayout(NodeConfig* config) {
  config->layout_cones.clear();
  if (config->layout_file.empty()) return;
  try {
    config->layout_cones = ConeGeometries(rig_model::LoadLayoutFile(config->layout_file));  // the one parser
  } catch (const rig_model::FileError& e) {
    throw std::invalid_argument(std::string("layout_file: ") + e.what());
  }
}

}  // namespace pose_ekf
