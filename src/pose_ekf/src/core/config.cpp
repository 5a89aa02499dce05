#include <cmath>
#include <sstream>

#include "pose_ekf/core/config.h"

namespace pose_ekf {
namespace {

// Appends "name must be ..." when value is not finite or not in its range.
void Check(std::ostringstream& err, const char* name, double value, double min, bool min_inclusive) {
  const bool ok = std::isfinite(value) && (min_inclusive ? value >= min : value > min);
  if (!ok) err << name << " must be " << (min_inclusive ? ">= " : "> ") << min << " (got " << value << "); ";
}

}  // namespace

std::string EkfConfig::Validate() const {
  std::ostringstream err;
  Check(err, "sigma_q_per_sqrt_s", sigma_q_per_sqrt_s, 0.0, false);
  Check(err, "sigma_omega_rad_s_per_sqrt_s", sigma_omega_rad_s_per_sqrt_s, 0.0, false);
  Check(err, "sigma_p_m_per_sqrt_s", sigma_p_m_per_sqrt_s, 0.0, true);
  Check(err, "sigma_v_m_s_per_sqrt_s", sigma_v_m_s_per_sqrt_s, 0.0, true);
  Check(err, "sigma_a_m_s2_per_sqrt_s", sigma_a_m_s2_per_sqrt_s, 0.0, false);
  Check(err, "sigma_gyro_bias_rad_s_per_sqrt_s", sigma_gyro_bias_rad_s_per_sqrt_s, 0.0, true);
  Check(err, "sigma_gyro_rad_s", sigma_gyro_rad_s, 0.0, false);
  Check(err, "sigma_accel_m_s2", sigma_accel_m_s2, 0.0, false);
  Check(err, "gravity_m_s2", gravity_m_s2, 0.0, false);
  if (!std::isfinite(accel_gate_m_s2)) err << "accel_gate_m_s2 must be finite; ";
  if (gyro_is_interval_mean && gyro_is_centred_interval_mean) {
    err << "gyro_is_interval_mean and gyro_is_centred_interval_mean exclude each other; ";
  }
  if (omega_walk_at_gyro && !gyro_is_interval_mean && !gyro_is_centred_interval_mean) {
    err << "omega_walk_at_gyro needs gyro_is_interval_mean or gyro_is_centred_interval_mean (a gyro that averages "
           "over its period; a point sample leaves the rate free to change between samples); ";
  }
  Check(err, "init_sigma_omega_rad_s", init_sigma_omega_rad_s, 0.0, false);
  Check(err, "init_sigma_v_m_s", init_sigma_v_m_s, 0.0, false);
  Check(err, "init_sigma_a_m_s2", init_sigma_a_m_s2, 0.0, false);
  Check(err, "init_sigma_gyro_bias_rad_s", init_sigma_gyro_bias_rad_s, 0.0, false);
  Check(err, "init_sigma_tilt_rad", init_sigma_tilt_rad, 0.0, false);
  Check(err, "init_sigma_heading_rad", init_sigma_heading_rad, 0.0, false);
  Check(err, "init_sigma_p_m", init_sigma_p_m, 0.0, false);
  Check(err, "sigma_angular_accel_rad_s2", sigma_angular_accel_rad_s2, 0.0, true);
  Check(err, "sigma_accel_bias_m_s2_per_sqrt_s", sigma_accel_bias_m_s2_per_sqrt_s, 0.0, true);
  Check(err, "init_sigma_accel_bias_m_s2", init_sigma_accel_bias_m_s2, 0.0, false);
  Check(err, "velocity_time_constant_s", velocity_time_constant_s, 0.0, true);
  Check(err, "accel_time_constant_s", accel_time_constant_s, 0.0, true);
  Check(err, "max_delay_s", max_delay_s, 0.0, true);
  Check(err, "time_jump_reset_s", time_jump_reset_s, 0.0, false);
  Check(err, "max_predict_step_s", max_predict_step_s, 0.0, false);
  if (!(camera_gate_chi2 >= 0.0 && std::isfinite(camera_gate_chi2))) {
    err << "camera_gate_chi2 must be finite and >= 0, 0 disables the gate (got " << camera_gate_chi2 << "); ";
  }
  if (reinit_after_rejections < 0) {
    err << "reinit_after_rejections must be >= 0, 0 never re-initialises (got " << reinit_after_rejections << "); ";
  }
  if (!(cone_gate_probability > 0.0 && cone_gate_probability <= 1.0)) {
    err << "cone_gate_probability must be in (0, 1], 1 disables the gate (got " << cone_gate_probability << "); ";
  }
  if (!(cone_joint_probability > 0.0 && cone_joint_probability <= 1.0)) {
    err << "cone_joint_probability must be in (0, 1], 1 disables the check (got " << cone_joint_probability << "); ";
  }
  Check(err, "reacquire_sigma_p_m", reacquire_sigma_p_m, 0.0, true);
  Check(err, "cone_ambiguity_margin", cone_ambiguity_margin, 0.0, true);
  Check(err, "cone_miss_cost", cone_miss_cost, 0.0, true);
  Check(err, "cone_unexplained_cost", cone_unexplained_cost, 0.0, true);
  if (cone_ambiguity_iterations < 0 || cone_ambiguity_iterations > 50) {
    err << "cone_ambiguity_iterations must be in [0, 50], 0 takes the first-order statistic (got "
        << cone_ambiguity_iterations << "); ";
  }
  if (cone_update_iterations < 0 || cone_update_iterations > 20) {
    err << "cone_update_iterations must be in [0, 20], 0 updates once (got " << cone_update_iterations << "); ";
  }
  Check(err, "cone_repeat_px", cone_repeat_px, 0.0, true);
  Check(err, "cone_repeat_max_s", cone_repeat_max_s, 0.0, false);
  Check(err, "cone_repeat_sigma_v_m_s", cone_repeat_sigma_v_m_s, 0.0, false);
  Check(err, "cone_repeat_sigma_omega_rad_s", cone_repeat_sigma_omega_rad_s, 0.0, false);
  if (reacquire_min_cones < 1) {
    err << "reacquire_min_cones must be >= 1, 1 fuses lone cones while re-acquiring (got " << reacquire_min_cones
        << "); ";
  }
  std::string problems = err.str();
  if (!problems.empty()) problems.resize(problems.size() - 2);  // every problem ends with "; "
  return problems;
}

}  // namespace pose_ekf
