// The measurement buffer of thesis 6.3, rebuilt for ROS message streams:
// measurements are applied in stamp order whatever order they arrive in. A
// camera frame (stamped at exposure) may arrive up to max_delay_s after IMU
// samples with later stamps; it is then inserted at its stamp and everything
// after it is re-applied from the stored state history. Older measurements are
// dropped and counted; a stream whose stamps jump back by more than
// time_jump_reset_s resets the filter (bag loop, simulator reset).
#pragma once

#include <cstdint>
#include <deque>

#include "pose_ekf/core/ekf_core.h"

namespace pose_ekf {

enum class AddResult {
  kApplied,            // appended at the newest stamp
  kReplayed,           // inserted in the past and later measurements re-applied
  kInitialized,        // first camera pose: the filter starts here
  kWaitingForCamera,   // IMU sample kept until the first camera pose arrives
  kDroppedLate,        // older than max_delay_s behind the newest stamp (or before initialisation)
  kRejectedNonFinite,  // NaN/inf in the message
  kRejectedInvalid,    // refused by the adapter: wrong frame, bad covariance, no data
  kGated,              // camera pose outside the chi-square gate: not fused
  kReinitialized,      // reinit_after_rejections gated poses in a row: the filter restarted from this one
};
const char* ToString(AddResult r);

struct BufferCounters {
  uint64_t camera_applied = 0, gyro_applied = 0, accel_applied = 0;
  uint64_t accel_gated = 0;   // |a| far from g (5.34)
  uint64_t camera_gated = 0;  // camera poses outside the chi-square gate (EkfConfig::camera_gate_chi2)
  double camera_gate_last_rejected_chi2 = 0.0;  // the gate statistic of the last of them
  uint64_t reinits = 0;                         // re-initialisations after reinit_after_rejections of them in a row
  uint64_t dropped_late = 0;                    // older than the buffer window
  uint64_t imu_before_start = 0;    // IMU samples older than the first pose (waiting for the cones is normal)
  uint64_t nan_rejected = 0;        // non-finite values or stamps
  uint64_t numerical_failures = 0;  // innovation covariance not positive definite
  uint64_t resets = 0;              // time jumped backwards
  uint64_t replays = 0;             // out-of-order insertions
  uint64_t camera_nis_count = 0;
  double camera_nis_sum = 0.0, camera_nis_last = 0.0;
};

class MeasurementBuffer {
 public:
  explicit MeasurementBuffer(const EkfConfig& config);

  AddResult AddCamera(const CameraMeasurement& m);
  AddResult AddImu(const ImuMeasurement& m);

  // Clears the history and the filter (counted as a reset).
  void Reset();
  void SetConfig(const EkfConfig& config);

  const EkfCore& filter() const { return ekf_; }
  const BufferCounters& counters() const { return counters_; }
  // True once after each reset caused by a time jump, so the caller warns once.
  bool TakeResetWarning();
  size_t history_size() const { return history_.size(); }
  // Gated camera poses since the last fused one (reset by a re-initialisation).
  int camera_gated_in_a_row() const { return camera_gated_in_a_row_; }

 private:
  struct Entry {
    double stamp_s = 0.0;
    bool is_camera = false;
    uint64_t seq = 0;  // arrival order, the last tie breaker
    CameraMeasurement camera;
    ImuMeasurement imu;
    FilterState after;  // the filter right after this measurement
  };
  static bool Before(const Entry& a, const Entry& b);

  AddResult Add(Entry e);
  bool DetectTimeJump(const Entry& e);
  AddResult InitializeFrom(const Entry& camera);
  void KeepGyroBias(const FilterState& before);
  AddResult ReinitializeFrom(size_t i);
  // Returns the camera update's result (kDisabled for an IMU sample).
  UpdateResult Apply(Entry& e, bool count);
  void Trim();

  EkfConfig config_;
  EkfCore ekf_;
  std::deque<Entry> history_;  // sorted by Before(); before initialisation: IMU samples only
  FilterState base_;           // the state before history_.front() (valid once initialised)
  BufferCounters counters_;
  uint64_t next_seq_ = 0;
  double last_camera_stamp_s_ = -1e300, last_imu_stamp_s_ = -1e300;
  bool reset_warning_ = false;
  int camera_gated_in_a_row_ = 0;  // counted when first applied, in arrival order
};

}  // namespace pose_ekf
