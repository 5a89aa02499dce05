#include "pose_ekf/node/node_config.h"

#include <ros/node_handle.h>
#include <yaml-cpp/yaml.h>

#include <stdexcept>

namespace pose_ekf {
namespace {

class NodeHandleSource : public ParamSource {
 public:
  explicit NodeHandleSource(const ros::NodeHandle& nh) : nh_(nh) {}
  void Get(const std::string& n, double* v) const override { nh_.param(n, *v, *v); }
  void Get(const std::string& n, bool* v) const override { nh_.param(n, *v, *v); }
  void Get(const std::string& n, std::string* v) const override { nh_.param(n, *v, *v); }

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

template <typename T>
void Get(const ParamSource& p, const std::string& name, T* value) {
  p.Get(name, value);  // absent: the struct's default stays
}

}  // namespace

NodeConfig LoadConfig(const ros::NodeHandle& private_nh) { return LoadConfig(NodeHandleSource(private_nh)); }

NodeConfig LoadConfigFile(const std::string& yaml_path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_path);
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument("cannot read config file " + yaml_path + ": " + e.what());
  }
  return LoadConfig(YamlSource(root));
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
