#include "rig_sim/imu_model.h"

#include "angles.h"

#include "imu_driver/core/crista_protocol.h"
#include "pose_math/rotation.h"
#include "rig_model/camera_imu.h"

#include <cmath>
#include <sstream>

#include <Eigen/Geometry>

namespace rig_sim {
namespace {

// Rounds to Crista counts, saturating at the int16 range and the sensor range.
int16_t Quantize(double value, double units_per_count, double range, bool* saturated) {
  double clipped = value;
  if (clipped > range) clipped = range, *saturated = true;
  if (clipped < -range) clipped = -range, *saturated = true;
  double raw = std::nearbyint(clipped / units_per_count);
  if (raw > 32767.0) raw = 32767.0, *saturated = true;
  if (raw < -32768.0) raw = -32768.0, *saturated = true;
  return static_cast<int16_t>(raw);
}

}  // namespace

Eigen::Matrix3d ImuConfig::R_camera_imu() const { return rig_model::MountRotation(mount_error_rpy_deg); }

rig_model::CameraImuExtrinsics ImuConfig::Extrinsics(const std::string& camera_frame,
                                                     const std::string& imu_frame) const {
  rig_model::CameraImuExtrinsics e;
  e.parent_frame = camera_frame;
  e.child_frame = imu_frame;
  e.q_camera_imu = Eigen::Quaterniond(R_camera_imu());
  e.p_imu_in_camera_m = p_imu_in_camera_m;
  return e;
}

std::string ImuConfig::Validate() const {
  if (!(rate_hz > 0.0 && rate_hz <= 2000.0)) return "rate_hz must be in (0, 2000]";
  if (!mount_error_rpy_deg.allFinite() || !p_imu_in_camera_m.allFinite())
    return "mount_error_rpy_deg and p_imu_in_camera_m must be finite";
  if (!(gyro_noise_deg_s >= 0 && gyro_bias_sigma_deg_s >= 0 && gyro_bias_walk_deg_s_sqrt_s >= 0 &&
        accel_noise_m_s2 >= 0 && accel_bias_sigma_m_s2 >= 0 && accel_bias_walk_m_s2_sqrt_s >= 0))
    return "noise parameters must be non-negative";
  if (!(gyro_range_deg_s > 0 && accel_range_m_s2 > 0)) return "ranges must be positive";
  return "";
}

ImuSimulator::ImuSimulator(const ImuConfig& config, const Trajectory& trajectory)
    : config_(config), trajectory_(trajectory), R_camera_imu_(config.R_camera_imu()), rng_(config.seed) {
  const std::string err = config.Validate();
  if (!err.empty()) throw std::invalid_argument("ImuConfig: " + err);
  for (int i = 0; i < 3; ++i) gyro_bias_rad_s_[i] = config.gyro_bias_sigma_deg_s * kDeg * normal_(rng_);
  for (int i = 0; i < 3; ++i) accel_bias_m_s2_[i] = config.accel_bias_sigma_m_s2 * normal_(rng_);
}

Eigen::Matrix3d ImuSimulator::R_cones_imu(double t) const { return trajectory_.At(t).R_cones_camera * R_camera_imu_; }

Eigen::Vector3d ImuSimulator::PositionImu(double t) const {
  const TruePose p = trajectory_.At(t);
  return p.p_camera_in_cones_m + p.R_cones_camera * config_.p_imu_in_camera_m;
}

Eigen::Vector3d ImuSimulator::SpecificForce(double t) const {
  // Acceleration of the IMU point itself, so the lever arm's centripetal and
  // tangential terms are included exactly; 4th-order central difference.
  const double h = 2e-3;
  const Eigen::Vector3d a_cones = (-PositionImu(t + 2 * h) + 16.0 * PositionImu(t + h) - 30.0 * PositionImu(t) +
                                   16.0 * PositionImu(t - h) - PositionImu(t - 2 * h)) /
                                  (12.0 * h * h);
  const Eigen::Vector3d g_cones(0.0, 0.0, -config_.gravity_m_s2);
  return R_cones_imu(t).transpose() * (a_cones - g_cones);
}

ImuSample ImuSimulator::Next() {
  ++index_;
  const double dt = 1.0 / config_.rate_hz;
  const double t = index_ * dt;
  ImuSample s;
  s.stamp_s = t;
  const Eigen::AngleAxisd delta(R_cones_imu(t - dt).transpose() * R_cones_imu(t));
  Eigen::Vector3d omega = delta.angle() * delta.axis() / dt;
  Eigen::Vector3d accel = SpecificForce(t - 0.5 * dt);
  if (config_.noise_enabled) {
    const double sqrt_dt = std::sqrt(dt);
    for (int i = 0; i < 3; ++i) {
      gyro_bias_rad_s_[i] += config_.gyro_bias_walk_deg_s_sqrt_s * kDeg * sqrt_dt * normal_(rng_);
      accel_bias_m_s2_[i] += config_.accel_bias_walk_m_s2_sqrt_s * sqrt_dt * normal_(rng_);
    }
    s.true_gyro_bias_rad_s = gyro_bias_rad_s_;
    s.true_accel_bias_m_s2 = accel_bias_m_s2_;
    for (int i = 0; i < 3; ++i) {
      omega[i] += gyro_bias_rad_s_[i] + config_.gyro_noise_deg_s * kDeg * normal_(rng_);
      accel[i] += accel_bias_m_s2_[i] + config_.accel_noise_m_s2 * normal_(rng_);
    }
  }
  if (config_.quantize) {
    for (int i = 0; i < 3; ++i) {
      s.gyro_raw[i] =
          Quantize(omega[i] / kDeg, imu_driver::kGyroDegPerSecPerCount, config_.gyro_range_deg_s, &s.saturated);
      s.accel_raw[i] = Quantize(accel[i], imu_driver::kAccelMPerS2PerCount, config_.accel_range_m_s2, &s.saturated);
      omega[i] = s.gyro_raw[i] * imu_driver::kGyroDegPerSecPerCount * kDeg;
      accel[i] = s.accel_raw[i] * imu_driver::kAccelMPerS2PerCount;
    }
  }
  s.omega_imu_rad_s = omega;
  s.accel_imu_m_s2 = accel;
  return s;
}

}  // namespace rig_sim
