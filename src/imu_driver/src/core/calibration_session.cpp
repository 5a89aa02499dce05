#include "imu_driver/core/calibration_session.h"

#include <sstream>

namespace imu_driver {

bool CalibrationSession::Start(double duration_s, std::string* message) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (running_) {
    *message = "a calibration is already running";
    return false;
  }
  estimator_.Clear();
  running_ = true;
  duration_s_ = duration_s;
  start_stamp_s_ = -1.0;
  std::ostringstream m;
  m << "collecting " << duration_s << " s of static gyro data: keep the IMU still; the result appears on "
    << "imu/is_calibrated and in the log";
  *message = m.str();
  return true;
}

std::optional<GyroBiasResult> CalibrationSession::Add(const ImuSample& s) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!running_) return std::nullopt;
  if (start_stamp_s_ < 0.0) start_stamp_s_ = s.stamp_s;
  estimator_.Add(Eigen::Vector3d(s.si.omega_imu_rad_s.data()), Eigen::Vector3d(s.si.accel_imu_m_s2.data()));
  if (s.stamp_s - start_stamp_s_ < duration_s_) return std::nullopt;
  running_ = false;
  GyroBiasResult r = estimator_.Compute();
  if (r.ok) current_ = GyroCalibration{r.bias_rad_s, r.sigma_rad_s, true};
  return r;
}

GyroCalibration CalibrationSession::current() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return current_;
}
bool CalibrationSession::running() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return running_;
}

}  // namespace imu_driver
