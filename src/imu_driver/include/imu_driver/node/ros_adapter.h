// ROS side of the driver: parameters -> DriverConfig, ImuSample -> sensor_msgs/Imu.
#pragma once

#include <ros/node_handle.h>
#include <sensor_msgs/Imu.h>

#include "imu_driver/core/calibration_session.h"
#include "imu_driver/core/driver_config.h"
#include "imu_driver/core/gyro_bias.h"

namespace imu_driver {

// Reads the private parameters; throws std::invalid_argument naming the
// parameter when a value is refused.
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
