// The Crista IMU on the rig: 100 Hz gyro and accelerometer in the IMU frame
// {I}, computed from the true motion of the camera, with the camera->IMU
// rotation, the lever arm, bias, white noise, bias random walk, the Crista's
// 16-bit quantisation and its range limits. ROS-free, deterministic per seed.
//
// Sampling convention: the sample stamped t_k describes the interval
// (t_k - dt, t_k]. The gyro is the mean body rate over it (the rotation vector
// of R_I(t_k - dt)^T R_I(t_k) divided by dt), so integrating it with a
// constant rate over that interval (2.71) is exact; the accelerometer is the
// specific force at the interval's midpoint.
#pragma once

#include <cstdint>
#include <random>
#include <string>

#include <Eigen/Core>

#include "rig_model/camera_imu.h"
#include "rig_sim/trajectory.h"

namespace rig_sim {

struct ImuConfig {
  double rate_hz = 100.0;
  // Mounting: R_camera_imu rotates IMU vectors into camera_optical. The default
  // is an IMU with x forward, y left, z up (REP-103 body axes) on a camera
  // looking forward, tilted by a small mounting error (roll, pitch, yaw, deg).
  Eigen::Vector3d mount_error_rpy_deg = Eigen::Vector3d(1.5, -2.0, 1.0);
  Eigen::Vector3d p_imu_in_camera_m = Eigen::Vector3d(0.02, 0.08, -0.06);  // the rig's ~10 cm lever arm
  double gravity_m_s2 = 9.81;
  // Noise (per-sample standard deviations at rate_hz, and random walks per sqrt(s)).
  bool noise_enabled = true;
  double gyro_noise_deg_s = 0.12;
  double gyro_bias_sigma_deg_s = 0.4;  // turn-on bias, drawn once per seed
  double gyro_bias_walk_deg_s_sqrt_s = 0.004;
  double accel_noise_m_s2 = 0.03;
  double accel_bias_sigma_m_s2 = 0.05;
  double accel_bias_walk_m_s2_sqrt_s = 0.0005;
  // Crista conversion: gyro raw*600/65536 deg/s, accel raw*196.1/65536 m/s^2.
  bool quantize = true;
  double gyro_range_deg_s = 300.0;
  double accel_range_m_s2 = 10.0 * 9.80665;
  uint64_t seed = 1;

  Eigen::Matrix3d R_camera_imu() const;  // rig_model::MountRotation(mount_error_rpy_deg)
  // The mount as the rig's extrinsics (rotation and lever arm), camera_frame -> imu_frame.
  rig_model::CameraImuExtrinsics Extrinsics(const std::string& camera_frame, const std::string& imu_frame) const;
  std::string Validate() const;
};

struct ImuSample {
  double stamp_s = 0.0;
  Eigen::Vector3d omega_imu_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_imu_m_s2 = Eigen::Vector3d::Zero();  // specific force
  int16_t gyro_raw[3] = {0, 0, 0};                           // Crista counts (valid when quantize)
  int16_t accel_raw[3] = {0, 0, 0};
  bool saturated = false;
  // Truth for this sample, for tests and the ground truth topics.
  Eigen::Vector3d true_gyro_bias_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d true_accel_bias_m_s2 = Eigen::Vector3d::Zero();
};

class ImuSimulator {
 public:
  ImuSimulator(const ImuConfig& config, const Trajectory& trajectory);
  // Orientation of {I} in cones at time t (truth).
  Eigen::Matrix3d R_cones_imu(double t_s) const;
  Eigen::Vector3d PositionImu(double t_s) const;
  // Next sample, at t = k / rate_hz for k = 1, 2, ... Deterministic sequence.
  ImuSample Next();
  // Noise-free specific force at t (for checks).
  Eigen::Vector3d SpecificForce(double t_s) const;

 private:
  ImuConfig config_;
  const Trajectory& trajectory_;
  Eigen::Matrix3d R_camera_imu_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  Eigen::Vector3d gyro_bias_rad_s_, accel_bias_m_s2_;
  int64_t index_ = 0;
};

}  // namespace rig_sim
