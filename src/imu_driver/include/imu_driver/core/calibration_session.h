// The imu/calibrate service's state: started from a service callback, fed by
// the I/O thread, finished after a fixed span of sample time. The gyro bias
// and σ in use are read by the I/O thread for every sample and replaced when
// a calibration succeeds.
#pragma once

#include <Eigen/Core>
#include <mutex>
#include <optional>
#include <string>

#include "imu_driver/core/crista_stream.h"
#include "imu_driver/core/gyro_bias.h"

namespace imu_driver {

// What the published messages use: the bias removed and the σ behind the covariance.
struct GyroCalibration {
  Eigen::Vector3d bias_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d sigma_rad_s = Eigen::Vector3d::Zero();
  bool calibrated = false;
};

class CalibrationSession {
 public:
  CalibrationSession(const GyroCalibration& initial, const GyroBiasConfig& config = GyroBiasConfig())
      : estimator_(config), current_(initial) {}

  // False (with the reason in *message) when one is already running.
  bool Start(double duration_s, std::string* message);
  // Feeds a raw (bias not removed) sample; returns the result once the span is over.
  std::optional<GyroBiasResult> Add(const ImuSample& s);

  GyroCalibration current() const;
  bool running() const;

 private:
  mutable std::mutex mutex_;  // Start() runs on the ROS callback thread, Add() on the I/O thread
  GyroBiasEstimator estimator_;
  bool running_ = false;
  double duration_s_ = 0.0;
  double start_stamp_s_ = -1.0;  // stamp of the first sample, -1 until it arrives
  GyroCalibration current_;
};

}  // namespace imu_driver
