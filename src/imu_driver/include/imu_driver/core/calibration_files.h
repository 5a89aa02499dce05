// The calibration files the driver and the launch files read: calibrate_camera_imu's camera-IMU
// YAML (3.2.2) and the gyro calibration YAML (3.2.1). Strict: an unknown or misspelt key, a value
// of the wrong kind, or a rotation that is not a unit quaternion throws rig_model::FileError naming
// the file, the line and the field. ROS-free.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

namespace imu_driver {

struct CameraImuFile {
  std::string parent_frame = "camera_optical";
  std::string child_frame = "imu";
  Eigen::Vector3d translation_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_camera_imu = Eigen::Quaterniond::Identity();
};

struct GyroCalibrationFile {
  std::optional<Eigen::Vector3d> gyro_bias_rad_s;         // absent: the driver is not calibrated
  std::optional<Eigen::Vector3d> gyro_noise_sigma_rad_s;  // absent: the configured default stays
};

// The keys under `camera_imu:` (calibrate_camera_imu writes them all; only the first four are used).
const std::vector<std::string>& CameraImuKeys();
// The keys of a gyro calibration file (the nodelet's parameter names).
const std::vector<std::string>& GyroCalibrationKeys();

CameraImuFile ReadCameraImuFile(const std::string& path);
GyroCalibrationFile ReadGyroCalibrationFile(const std::string& path);

}  // namespace imu_driver
