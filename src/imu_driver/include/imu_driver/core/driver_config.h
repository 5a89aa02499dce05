// Everything the driver nodelet is configured with, with units in the names.
// Filled and validated by LoadConfig (ros_adapter.h); the core never sees ROS.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

#include "imu_driver/core/serial_reader.h"

namespace imu_driver {

struct DriverConfig {
  SerialReaderConfig reader;  // ~port, ~baud, ~rate_hz, ~retry_*, clock-model settings
  std::string frame_id = "imu";
  // REP-145: the stamp is when the measurement applies. A Crista sample averages the interval before
  // it is sent, so by default the stamp is moved from the frame's arrival back by half a sample
  // period, to the interval's midpoint (the convention rig_sim and pose_ekf share).
  bool stamp_at_interval_midpoint = true;
  // Noise and bias from the static calibration (3.2.1); the covariances are σ².
  Eigen::Vector3d gyro_bias_rad_s = Eigen::Vector3d::Zero();
  bool gyro_bias_calibrated = false;  // true when a bias was loaded or measured
  bool subtract_gyro_bias = true;
  Eigen::Vector3d gyro_noise_sigma_rad_s = Eigen::Vector3d::Constant(0.005);
  Eigen::Vector3d accel_noise_sigma_m_s2 = Eigen::Vector3d::Constant(0.05);
  // Optional output in the camera frame (3.26) with the 3.2.2 calibration.
  bool publish_in_camera_frame = false;
  std::string camera_frame_id = "camera_optical";
  Eigen::Quaterniond q_camera_imu = Eigen::Quaterniond::Identity();
  // Calibration service.
  double calibration_duration_s = 5.0;
  bool calibrate_on_start = false;
  std::string calibration_output_file;  // YAML written after a successful calibration, if set
  // Diagnostics.
  double stale_after_s = 0.5;  // time without a sample that is an error
  double rate_tolerance = 0.1;
};

}  // namespace imu_driver
