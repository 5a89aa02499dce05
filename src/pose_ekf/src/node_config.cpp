#include "pose_ekf/node_config.h"

#include <ros/node_handle.h>

#include <stdexcept>

namespace pose_ekf {
namespace {

template <typename T>
void Get(const ros::NodeHandle& nh, const std::string& name, T* value) {
  nh.param(name, *value, *value);  // default: the struct's value
}

}  // namespace

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

NodeConfig LoadConfig(const ros::NodeHandle& nh) {
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
  Get(nh, "max_delay_s", &e.max_delay_s);
  Get(nh, "time_jump_reset_s", &e.time_jump_reset_s);
  Get(nh, "max_predict_step_s", &e.max_predict_step_s);
  const std::string err = e.Validate();
  if (!err.empty()) throw std::invalid_argument(err);
  return c;
}

}  // namespace pose_ekf
