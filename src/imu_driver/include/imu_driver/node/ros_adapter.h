// ROS side of the driver: parameters -> DriverConfig, ImuSample -> sensor_msgs/Imu.
#pragma once

#include <ros/node_handle.h>
#include <sensor_msgs/Imu.h>

#include "imu_driver/core/calibration_session.h"
#include "imu_driver/core/driver_config.h"
#include "imu_driver/core/gyro_bias.h"
#include "rig_model/param_table.h"

namespace imu_driver {

// What the private parameters hold: the DriverConfig, the enum's index and the files LoadConfig reads.
struct DriverParams {
  DriverConfig config;
  int time_source = 0;                // StreamConfig::TimeSource: sequence (0) or pps (1)
  std::string config_file;            // the YAML imu_driver.launch loaded, named in errors
  std::string gyro_calibration_file;  // 3.2.1 calibration YAML, overriding gyro_* parameters
  std::string camera_imu_file;        // 3.2.2 calibration YAML, overriding camera_imu/rotation_xyzw
};

// Every scalar private parameter, nested ones by their path under ~ ("time_sync/window_s"). The
// lists (gyro_bias_rad_s, ..., camera_imu/rotation_xyzw) are read by LoadConfig itself.
const rig_model::ParamTable<DriverParams>& DriverParamTable();

// Reads the private parameters (rig_model::LoadParams: type-checked, unknown names refused with
// the nearest known one) and the calibration files; throws std::invalid_argument naming the
// parameter or the file when a value is refused.
DriverConfig LoadConfig(const ros::NodeHandle& pnh);

// REP-145 message: no orientation (orientation_covariance[0] = -1), diagonal
// covariances from the calibration σ (gyro) and the configured accel σ, bias
// removed when configured, and in the camera frame when configured (3.26).
void FillImuMessage(const ImuSample& sample, const DriverConfig& config, const GyroCalibration& gyro,
                    sensor_msgs::Imu* msg);

// The YAML the calibration service writes; the keys are the nodelet's
// parameter names, so `rosparam load` into the node's namespace applies it.
std::string GyroCalibrationYaml(const GyroBiasResult& r);

}  // namespace imu_driver
