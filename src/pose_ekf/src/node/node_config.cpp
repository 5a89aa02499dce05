#include "pose_ekf/node/node_config.h"

#include <ros/node_handle.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <stdexcept>

#include "rig_model/ros/params.h"
#include "rig_model/strict_yaml.h"

namespace pose_ekf {
namespace {

class NodeHandleSource : public ParamSource {
 public:
  explicit NodeHandleSource(const ros::NodeHandle& nh) : nh_(nh) {}
  // Absent: *v stays; a wrong type throws naming the parameter (nh.param() kept the default silently).
  void Get(const std::string& n, double* v) const override { rig_model::GetParam(nh_, n, v); }
  void Get(const std::string& n, bool* v) const override { rig_model::GetParam(nh_, n, v); }
  void Get(const std::string& n, std::string* v) const override { rig_model::GetParam(nh_, n, v); }

 private:
  const ros::NodeHandle& nh_;
};

class YamlSource : public ParamSource {
 public:
  explicit YamlSource(YAML::Node root) : root_(std::move(root)) {}
  void Get(const std::string& n, double* v) const override { Read(n, v); }
  void Get(const std::string& n, bool* v) const override { Read(n, v); }
  void Get(const std::string& n, std::string* v) const override { Read(n, v); }

 private:
  template <typename T>
  void Read(const std::string& n, T* v) const {
    if (!root_[n]) return;
    try {
      *v = root_[n].as<T>();
    } catch (const YAML::Exception& e) {
      throw std::invalid_argument(n + " has the wrong type: " + e.what());
    }
  }
  YAML::Node root_;
};

// Records the names LoadConfig asks for: the known names are the loader's own, never a second list.
class NameRecorder : public ParamSource {
 public:
  void Get(const std::string& n, double*) const override { names.push_back(n); }
  void Get(const std::string& n, bool*) const override { names.push_back(n); }
  void Get(const std::string& n, std::string*) const override { names.push_back(n); }
  mutable std::vector<std::string> names;
};

// ~config_file: set by pose_ekf.launch to the YAML it loaded here, so that errors name the file.
const char kConfigFileParam[] = "config_file";

// Throws std::invalid_argument "file:line: unknown key 'x' (did you mean 'y'?)" for a key LoadConfig
// does not read; returns the file's mapping.
YAML::Node StrictFile(const std::string& yaml_path) {
  try {
    YAML::Node root = rig_model::LoadYamlFile(yaml_path);
    if (root.IsNull()) return YAML::Node(YAML::NodeType::Map);  // comments only: all defaults
    rig_model::StrictReader(yaml_path).CheckKeys(root, ParamNames(), "");
    return root;
  } catch (const rig_model::FileError& e) {
    throw std::invalid_argument(e.what());
  }
}

template <typename T>
void Get(const ParamSource& p, const std::string& name, T* value) {
  p.Get(name, value);  // absent: the struct's default stays
}

}  // namespace

std::vector<std::string> ParamNames() {
  NameRecorder recorder;
  LoadConfig(recorder);
  return recorder.names;
}

NodeConfig LoadConfig(const ros::NodeHandle& private_nh) {
  std::string file;
  rig_model::GetParam(private_nh, kConfigFileParam, &file);
  if (!file.empty()) StrictFile(file);  // a misspelt key, with its line
  std::vector<std::string> known = ParamNames();
  known.insert(known.end(), {kConfigFileParam, "diagnostic_period"});  // the note and diagnostic_updater's own
  try {
    rig_model::CheckParamNames(private_nh, known);
    return LoadConfig(NodeHandleSource(private_nh));
  } catch (const std::invalid_argument& e) {
    if (file.empty()) throw;
    throw std::invalid_argument(std::string(e.what()) + " (parameters loaded from " + file + ")");
  }
}

NodeConfig LoadConfigFile(const std::string& yaml_path) {
  const YAML::Node root = StrictFile(yaml_path);
  try {
    return LoadConfig(YamlSource(root));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(yaml_path + ": " + e.what());
  }
}

AccelMode ParseAccelMode(const std::string& s) {
  if (s == "off") return AccelMode::kOff;
  if (s == "orientation") return AccelMode::kOrientation;
  if (s == "position_orientation") return AccelMode::kPositionAndOrientation;
  throw std::invalid_argument("accel_mode must be off, orientation or position_orientation (got '" + s + "')");
}

QuatIntegration ParseQuatIntegration(const std::string& s) {
  if (s == "first_order") return QuatIntegration::kFirstOrder;
  if (s == "exact") return QuatIntegration::kExact;
  throw std::invalid_argument("quat_integration must be first_order or exact (got '" + s + "')");
}

NodeConfig LoadConfig(const ParamSource& nh) {
  NodeConfig c;
  Get(nh, "cones_frame", &c.cones_frame);
  Get(nh, "camera_frame", &c.camera_frame);
  Get(nh, "publish_tf", &c.publish_tf);
  Get(nh, "output_rate_hz", &c.output_rate_hz);
  Get(nh, "imu_expected_rate_hz", &c.imu_expected_rate_hz);
  Get(nh, "camera_expected_rate_hz", &c.camera_expected_rate_hz);
  Get(nh, "tf_timeout_s", &c.tf_timeout_s);
  if (c.cones_frame.empty()) throw std::invalid_argument("cones_frame must not be empty");
  if (c.camera_frame.empty()) throw std::invalid_argument("camera_frame must not be empty");
  if (!(c.output_rate_hz >= 0.0)) throw std::invalid_argument("output_rate_hz must be >= 0");
  if (!(c.imu_expected_rate_hz > 0.0)) throw std::invalid_argument("imu_expected_rate_hz must be > 0");
  if (!(c.camera_expected_rate_hz > 0.0)) throw std::invalid_argument("camera_expected_rate_hz must be > 0");
  if (!(c.tf_timeout_s >= 0.0)) throw std::invalid_argument("tf_timeout_s must be >= 0");

  EkfConfig& e = c.ekf;
  Get(nh, "sigma_q_per_sqrt_s", &e.sigma_q_per_sqrt_s);
  Get(nh, "sigma_omega_rad_s_per_sqrt_s", &e.sigma_omega_rad_s_per_sqrt_s);
  Get(nh, "sigma_p_m_per_sqrt_s", &e.sigma_p_m_per_sqrt_s);
  Get(nh, "sigma_v_m_s_per_sqrt_s", &e.sigma_v_m_s_per_sqrt_s);
  Get(nh, "sigma_a_m_s2_per_sqrt_s", &e.sigma_a_m_s2_per_sqrt_s);
  Get(nh, "sigma_gyro_bias_rad_s_per_sqrt_s", &e.sigma_gyro_bias_rad_s_per_sqrt_s);
  Get(nh, "sigma_gyro_rad_s", &e.sigma_gyro_rad_s);
  Get(nh, "sigma_accel_m_s2", &e.sigma_accel_m_s2);
  Get(nh, "use_message_imu_covariance", &e.use_message_imu_covariance);
  Get(nh, "use_camera", &e.use_camera);
  Get(nh, "use_gyro", &e.use_gyro);
  Get(nh, "gyro_is_interval_mean", &e.gyro_is_interval_mean);
  std::string accel_mode = "position_orientation", quat_integration = "first_order";
  Get(nh, "accel_mode", &accel_mode);
  Get(nh, "quat_integration", &quat_integration);
  e.accel_mode = ParseAccelMode(accel_mode);
  bool use_accel = true;  // the GUI switch; accel_mode says which model when on
  Get(nh, "use_accel", &use_accel);
  c.accel_mode_when_on = e.accel_mode;
  if (!use_accel) e.accel_mode = AccelMode::kOff;
  e.quat_integration = ParseQuatIntegration(quat_integration);
  Get(nh, "gravity_m_s2", &e.gravity_m_s2);
  Get(nh, "accel_gate_m_s2", &e.accel_gate_m_s2);
  Get(nh, "camera_gate_chi2", &e.camera_gate_chi2);
  double reinit_after_rejections = e.reinit_after_rejections;  // an integer parameter, read as a number
  Get(nh, "reinit_after_rejections", &reinit_after_rejections);
  if (!(reinit_after_rejections >= 0.0 && reinit_after_rejections <= 1e6 &&
        reinit_after_rejections == std::floor(reinit_after_rejections))) {
    throw std::invalid_argument(
        "reinit_after_rejections must be a whole number in [0, 1e6], 0 never re-initialises (got " +
        std::to_string(reinit_after_rejections) + ")");
  }
  e.reinit_after_rejections = static_cast<int>(reinit_after_rejections);
  Get(nh, "estimate_gyro_bias", &e.estimate_gyro_bias);
  Get(nh, "joseph_update", &e.joseph_update);
  Get(nh, "init_sigma_omega_rad_s", &e.init_sigma_omega_rad_s);
  Get(nh, "init_sigma_v_m_s", &e.init_sigma_v_m_s);
  Get(nh, "init_sigma_a_m_s2", &e.init_sigma_a_m_s2);
  Get(nh, "init_sigma_gyro_bias_rad_s", &e.init_sigma_gyro_bias_rad_s);
  Get(nh, "init_from_gravity", &e.init_from_gravity);
  Get(nh, "init_sigma_tilt_rad", &e.init_sigma_tilt_rad);
  Get(nh, "init_sigma_heading_rad", &e.init_sigma_heading_rad);
  Get(nh, "init_sigma_p_m", &e.init_sigma_p_m);
  Get(nh, "max_delay_s", &e.max_delay_s);
  Get(nh, "time_jump_reset_s", &e.time_jump_reset_s);
  Get(nh, "max_predict_step_s", &e.max_predict_step_s);
  const std::string err = e.Validate();
  if (!err.empty()) throw std::invalid_argument(err);
  return c;
}

}  // namespace pose_ekf
