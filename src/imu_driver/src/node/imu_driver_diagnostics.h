// The "Crista IMU" diagnostic task: connection state, counts by kind of
// reject, sequence gaps, time since the last sample, clock model.
#pragma once

#include <diagnostic_updater/DiagnosticStatusWrapper.h>

#include "imu_driver/core/calibration_session.h"
#include "imu_driver/core/driver_config.h"
#include "imu_driver/core/serial_reader.h"

namespace imu_driver {

class DriverDiagnostics {
 public:
  // now_s is on the same clock as the samples' arrival times.
  void Fill(const SerialReaderStatus& st, const DriverConfig& config, const GyroCalibration& gyro, double now_s,
            diagnostic_updater::DiagnosticStatusWrapper* s);

 private:
  uint64_t last_rejects_ = 0;
  uint64_t last_gaps_ = 0;
};

}  // namespace imu_driver
