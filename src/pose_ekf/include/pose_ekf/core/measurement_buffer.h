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
  // Tightly coupled path (camera_update, cone_measurement.h):
  kSuperseded,  // not fused: the same image's cone observations were (pose), or its pose initialised the filter (cones)
  kNotUsed,     // cone observations with camera_update = pose (or the camera switched off, or no cones)
  kRepeated,    // cone observations of the same view as the last fused ones (EkfConfig::cone_repeat_px)
};
const char* ToString(AddResult r);

struct BufferCounters {
  uint64_t camera_applied = 0, gyro_applied = 0, accel_applied = 0;
  uint64_t accel_gated = 0;   // |a| far from g (5.34)
  uint64_t camera_gated = 0;  // camera poses outside the chi-square gate (EkfConfig::camera_gate_chi2)
  double camera_gate_last_rejected_chi2 = 0.0;  // the gate statistic of the last of them
  uint64_t reinits = 0;                         // re-initialisations after reinit_after_rejections of them in a row
  uint64_t dropped_late = 0;                    // older than the buffer window
  uint64_t cone_frames_dropped_late = 0;        // cone observations older than the buffer window
  uint64_t imu_before_start = 0;    // IMU samples older than the first pose (waiting for the cones is normal)
  uint64_t nan_rejected = 0;        // non-finite values or stamps
  uint64_t numerical_failures = 0;  // innovation covariance not positive definite
  uint64_t resets = 0;              // time jumped backwards
  uint64_t replays = 0;             // out-of-order insertions
  uint64_t camera_nis_count = 0;
  double camera_nis_sum = 0.0, camera_nis_last = 0.0;
  // Cone observations (camera_update = cones).
  uint64_t cone_frames_applied = 0;             // frames with at least one cone fused
  uint64_t cone_frames_rejected = 0;            // frames with none fused: they count toward reinit_after_rejections
  uint64_t cones_applied = 0, cones_gated = 0;  // per cone; gated: outside the per-cone chi-square gate
  uint64_t cones_joint_dropped = 0;             // dropped because their frame's joint NIS failed
  uint64_t cones_behind_camera = 0;             // a model point behind the predicted camera
  double cone_last_rejected_chi2 = 0.0;         // the largest per-cone statistic of the last frame with a rejection
  uint64_t cone_frames_before_start = 0;        // before the first pose initialised the filter
  uint64_t cone_frames_not_used = 0;            // camera_update = pose
  uint64_t cone_frames_superseded = 0;          // their image's pose (re-)initialised the filter
  uint64_t poses_superseded = 0;                // poses not fused because their image's cones were
  uint64_t reacquisitions = 0;                  // poses that re-initialised the filter in cones mode (also in reinits)
  uint64_t cone_frames_too_few = 0;             // re-acquiring: fewer than reacquire_min_cones cones passed, none fused
  uint64_t cone_frames_ambiguous = 0;           // a lone cone another layout cone fits nearly as well: not fused
  uint64_t cone_frames_repeated = 0;            // the same view as the last fused frame (cone_repeat_px): not fused
  uint64_t cone_nis_count = 0;
  double cone_nis_sum = 0.0, cone_nis_last = 0.0;  // the joint NIS of a fused frame
  uint64_t cone_nis_dof = 0;                       // the degrees of freedom of cone_nis_sum (kConeDof per fused cone)
};

class MeasurementBuffer {
 public:
  explicit MeasurementBuffer(const EkfConfig& config);

  AddResult AddCamera(const CameraMeasurement& m);
  AddResult AddImu(const ImuMeasurement& m);
  // One image's cone observations, stamped at exposure like AddCamera, applied and replayed the same
  // way; see EkfConfig::camera_update for how they and the poses interact.
  AddResult AddCones(const ConeFrame& f);

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
  // Cones mode: the next camera pose re-initialises the filter (after reinit_after_rejections
  // rejected cone frames in a row, or, once cone frames arrive, with the position sigma above
  // reacquire_sigma_p_m).
  bool ReacquireDue() const;
  double PositionSigmaM() const;  // the largest standard deviation of the position (0 uninitialised)
  const ConeFrameResult& last_cone_frame() const { return last_cone_frame_; }

 private:
  struct Entry {
    double stamp_s = 0.0;
    bool is_camera = false;  // a pose, or cone observations (is_cones)
    bool is_cones = false;
    bool superseded = false;                         // a pose whose image's cones are in the history: not fused
    UpdateResult counted = UpdateResult::kDisabled;  // how a pose was counted when it arrived
    uint64_t seq = 0;                                // arrival order, the last tie breaker
    CameraMeasurement camera;
    ImuMeasurement imu;
    ConeFrame cones;
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
  void UncountPose(Entry& pose);
  void Trim();
  void MarkSuperseded(size_t i);
  void TallyCones(UpdateResult r, const ConeFrameResult& res);

  EkfConfig config_;
  EkfCore ekf_;
  std::deque<Entry> history_;  // sorted by Before(); before initialisation: IMU samples only
  FilterState base_;           // the state before history_.front() (valid once initialised)
  BufferCounters counters_;
  uint64_t next_seq_ = 0;
  double last_camera_stamp_s_ = -1e300, last_imu_stamp_s_ = -1e300;
  bool reset_warning_ = false;
  int camera_gated_in_a_row_ = 0;           // counted when first applied, in arrival order
  bool reacquire_pending_ = false;          // cones mode: reinit_after_rejections cone frames rejected in a row
  bool cones_seen_ = false;                 // a cone frame was added since the last reset
  double last_pose_init_stamp_s_ = -1e300;  // the pose the filter last (re-)initialised from
  ConeFrameResult last_cone_frame_;
};

}  // namespace pose_ekf
