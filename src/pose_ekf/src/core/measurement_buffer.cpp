#include "pose_ekf/core/measurement_buffer.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace pose_ekf {
namespace {

bool Finite(const CameraMeasurement& m) { return std::isfinite(m.stamp_s) && PoseUsable(m); }

bool Finite(const ImuMeasurement& m) {
  return std::isfinite(m.stamp_s) && (!m.has_gyro || m.omega_camera_rad_s.allFinite()) &&
         (!m.has_accel || m.accel_camera_m_s2.allFinite()) &&
         (!m.has_covariance || (m.gyro_cov.allFinite() && m.accel_cov.allFinite()));
}

}  // namespace

const char* ToString(AddResult r) {
  switch (r) {
    case AddResult::kApplied:
      return "applied";
    case AddResult::kReplayed:
      return "replayed";
    case AddResult::kInitialized:
      return "initialized";
    case AddResult::kWaitingForCamera:
      return "waiting for camera";
    case AddResult::kDroppedLate:
      return "dropped (late)";
    case AddResult::kRejectedNonFinite:
      return "rejected (non-finite)";
    case AddResult::kRejectedInvalid:
      return "rejected (invalid)";
    case AddResult::kGated:
      return "rejected (chi2 gate)";
    case AddResult::kReinitialized:
      return "re-initialised (chi2 gate)";
    case AddResult::kSuperseded:
      return "superseded (the same image was fused once)";
    case AddResult::kNotUsed:
      return "not used (camera_update)";
    case AddResult::kRepeated:
      return "not fused (the same view as the last fused frame, cone_repeat_px)";
  }
  return "?";
}

MeasurementBuffer::MeasurementBuffer(const EkfConfig& config) : config_(config), ekf_(config) {}

void MeasurementBuffer::SetConfig(const EkfConfig& config) {
  ekf_.SetConfig(config);  // throws on invalid config before anything changes
  config_ = config;
}

bool MeasurementBuffer::Before(const Entry& a, const Entry& b) {
  if (a.stamp_s != b.stamp_s) return a.stamp_s < b.stamp_s;
  if (a.is_camera != b.is_camera) return a.is_camera;  // equal stamps: camera first, deterministically
  if (a.is_cones != b.is_cones) return a.is_cones;     // an image's cones before its pose (superseding)
  return a.seq < b.seq;
}

AddResult MeasurementBuffer::AddCamera(const CameraMeasurement& m) {
  if (!Finite(m)) {
    ++counters_.nan_rejected;
    return AddResult::kRejectedNonFinite;
  }
  Entry e;
  e.stamp_s = m.stamp_s;
  e.is_camera = true;
  e.camera = m;
  return Add(std::move(e));
}

AddResult MeasurementBuffer::AddCones(const ConeFrame& f) {
  if (!CheckConeFrame(f).empty()) {
    ++counters_.nan_rejected;
    return AddResult::kRejectedNonFinite;
  }
  if (config_.camera_update != CameraUpdate::kCones || !config_.use_camera || f.cones.empty()) {
    ++counters_.cone_frames_not_used;
    return AddResult::kNotUsed;
  }
  cones_seen_ = true;
  Entry e;
  e.stamp_s = f.stamp_s;
  e.is_camera = e.is_cones = true;
  e.cones = f;
  return Add(std::move(e));
}

double MeasurementBuffer::PositionSigmaM() const {
  if (!ekf_.initialized()) return 0.0;
  const Eigen::Matrix3d P = ekf_.state().P.block<3, 3>(kP, kP);
  return std::sqrt(std::max(
      0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(P, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff()));
}

bool MeasurementBuffer::ReacquireDue() const {
  if (config_.camera_update != CameraUpdate::kCones || !ekf_.initialized()) return false;
  // The sigma test only once cone observations arrive: a stream of poses alone is fused as before.
  return reacquire_pending_ ||
         (cones_seen_ && config_.reacquire_sigma_p_m > 0.0 && PositionSigmaM() > config_.reacquire_sigma_p_m);
}

// A pose and cone observations of one image carry the same information: the pose is not fused
// when the cones (which sort just before it) are in the history.
void MeasurementBuffer::MarkSuperseded(size_t i) {
  const Entry& e = history_[i];
  if (!e.is_camera || config_.camera_update != CameraUpdate::kCones) return;
  if (e.is_cones) {
    for (size_t j = i + 1; j < history_.size() && history_[j].stamp_s == e.stamp_s; ++j) {
      Entry& pose = history_[j];
      if (pose.is_camera && !pose.is_cones && !pose.superseded) {
        pose.superseded = true;
        UncountPose(pose);  // counted when it arrived before its cones; now it is not fused
        ++counters_.poses_superseded;
      }
    }
  } else if (i > 0 && history_[i - 1].is_cones && history_[i - 1].stamp_s == e.stamp_s) {
    history_[i].superseded = true;
    ++counters_.poses_superseded;
  }
}

// Every pose is counted once, by what became of it: one fused when it arrived and
// superseded by its image's cones later leaves the count it had.
void MeasurementBuffer::UncountPose(Entry& pose) {
  uint64_t* counter = nullptr;
  switch (pose.counted) {
    case UpdateResult::kApplied:
      counter = &counters_.camera_applied;
      break;
    case UpdateResult::kGated:
      counter = &counters_.camera_gated;
      break;
    case UpdateResult::kRejectedNonFinite:
      counter = &counters_.nan_rejected;
      break;
    case UpdateResult::kNumericalFailure:
      counter = &counters_.numerical_failures;
      break;
    default:
      break;
  }
  if (counter && *counter > 0) --*counter;
  pose.counted = UpdateResult::kDisabled;
}

AddResult MeasurementBuffer::AddImu(const ImuMeasurement& m) {
  if (!Finite(m)) {
    ++counters_.nan_rejected;
    return AddResult::kRejectedNonFinite;
  }
  Entry e;
  e.stamp_s = m.stamp_s;
  e.imu = m;
  return Add(std::move(e));
}

void MeasurementBuffer::Reset() {
  history_.clear();
  ekf_.Reset();
  last_camera_stamp_s_ = last_imu_stamp_s_ = -1e300;
  camera_gated_in_a_row_ = 0;
  reacquire_pending_ = cones_seen_ = false;
  last_pose_init_stamp_s_ = -1e300;
  ++counters_.resets;
}

bool MeasurementBuffer::TakeResetWarning() {
  const bool w = reset_warning_;
  reset_warning_ = false;
  return w;
}

// Each stream is in order within itself; a big step back in one means time
// itself jumped back (design: clear state with one warning).
bool MeasurementBuffer::DetectTimeJump(const Entry& e) {
  double& last = e.is_camera ? last_camera_stamp_s_ : last_imu_stamp_s_;
  const bool jump = e.stamp_s < last - config_.time_jump_reset_s;
  if (jump) {
    Reset();
    reset_warning_ = true;
  }
  last = std::max(e.is_camera ? last_camera_stamp_s_ : last_imu_stamp_s_, e.stamp_s);
  return jump;
}

AddResult MeasurementBuffer::Add(Entry e) {
  DetectTimeJump(e);
  e.seq = next_seq_++;
  const double newest = history_.empty() ? (ekf_.initialized() ? base_.stamp_s : -1e300) : history_.back().stamp_s;
  if (e.stamp_s < newest - config_.max_delay_s || (ekf_.initialized() && e.stamp_s < base_.stamp_s)) {
    ++(e.is_cones ? counters_.cone_frames_dropped_late : counters_.dropped_late);
    return AddResult::kDroppedLate;
  }
  if (!ekf_.initialized() && e.is_cones) {
    ++counters_.cone_frames_before_start;  // a pose starts the filter
    return AddResult::kWaitingForCamera;
  }
  if (e.is_cones && e.stamp_s == last_pose_init_stamp_s_) {
    ++counters_.cone_frames_superseded;  // this image's pose (re-)initialised the filter
    return AddResult::kSuperseded;
  }
  if (!ekf_.initialized()) {
    if (e.is_camera && config_.use_camera) return InitializeFrom(e);
    if (!e.is_camera && config_.init_from_gravity && e.imu.has_accel &&
        ekf_.InitializeFromGravity(e.stamp_s, e.imu.accel_camera_m_s2)) {
      counters_.imu_before_start += history_.size();
      history_.clear();
      base_ = ekf_.state();
      return AddResult::kInitialized;
    }
    if (!e.is_camera) {
      history_.insert(std::upper_bound(history_.begin(), history_.end(), e, Before), std::move(e));
      Trim();
    }
    return AddResult::kWaitingForCamera;
  }
  const auto pos = std::upper_bound(history_.begin(), history_.end(), e, Before);
  const bool at_end = pos == history_.end();
  size_t i = static_cast<size_t>(pos - history_.begin());
  const bool reacquire = e.is_camera && !e.is_cones && config_.use_camera && ReacquireDue();
  history_.insert(pos, std::move(e));
  if (reacquire) {
    ++counters_.reacquisitions;
    return ReinitializeFrom(i);
  }
  MarkSuperseded(i);
  if (!at_end) {
    ekf_.Restore(i == 0 ? base_ : history_[i - 1].after);
    ++counters_.replays;
  }
  UpdateResult camera = UpdateResult::kDisabled;
  for (size_t j = i; j < history_.size(); ++j) {
    const UpdateResult r = Apply(history_[j], j == i);  // re-applied measurements are not counted twice
    if (j == i) camera = r;
    history_[j].after = ekf_.state();
  }
  if (camera == UpdateResult::kApplied) camera_gated_in_a_row_ = 0, reacquire_pending_ = false;
  if (camera == UpdateResult::kGated && history_[i].is_cones) {
    // Cone observations cannot initialise the filter: the next pose will (Add, ReacquireDue).
    ++camera_gated_in_a_row_;
    reacquire_pending_ |=
        config_.reinit_after_rejections > 0 && camera_gated_in_a_row_ >= config_.reinit_after_rejections;
  } else if (camera == UpdateResult::kGated) {
    ++camera_gated_in_a_row_;
    if (config_.reinit_after_rejections > 0 && camera_gated_in_a_row_ >= config_.reinit_after_rejections) {
      return ReinitializeFrom(i);
    }
  }
  const bool superseded = history_[i].superseded;
  const bool repeated = history_[i].is_cones && camera == UpdateResult::kDisabled && last_cone_frame_.repeated;
  Trim();
  if (camera == UpdateResult::kGated) return AddResult::kGated;
  if (superseded) return AddResult::kSuperseded;
  if (repeated) return AddResult::kRepeated;
  return at_end ? AddResult::kApplied : AddResult::kReplayed;
}

// The camera has disagreed with the filter reinit_after_rejections times in a
// row: trust the camera. Like the first initialisation, the filter restarts
// from this pose (and the initial sigmas of the rest); later measurements
// already received are re-applied, older ones are forgotten.
AddResult MeasurementBuffer::ReinitializeFrom(size_t i) {
  const Entry camera = history_[i];
  const FilterState before = ekf_.state();
  history_.erase(history_.begin(), history_.begin() + static_cast<std::ptrdiff_t>(i) + 1);
  ekf_.Initialize(camera.camera);  // usable: AddCamera checked it
  KeepGyroBias(before);
  base_ = ekf_.state();
  for (Entry& e : history_) {
    Apply(e, false);
    e.after = ekf_.state();
  }
  camera_gated_in_a_row_ = 0;
  reacquire_pending_ = false;
  last_pose_init_stamp_s_ = camera.stamp_s;
  ++counters_.reinits;
  Trim();
  return AddResult::kReinitialized;
}

// A camera that disagrees with the filter says nothing about the gyro: the bias learned so far (and its
// variance) survives a re-initialisation, when both states estimate it; so does the accelerometer bias.
void MeasurementBuffer::KeepGyroBias(const FilterState& before) {
  FilterState s = ekf_.state();
  const int n = static_cast<int>(s.x.size()), nb = n - kBaseStates;
  if (before.x.size() != s.x.size() || nb <= 0) return;
  s.x.segment(kB, nb) = before.x.segment(kB, nb);
  s.P.block(kB, kB, nb, nb) = before.P.block(kB, kB, nb, nb);
  ekf_.Restore(s);
}

AddResult MeasurementBuffer::InitializeFrom(const Entry& camera) {
  if (!ekf_.Initialize(camera.camera)) {
    ++counters_.nan_rejected;
    return AddResult::kRejectedNonFinite;
  }
  ++counters_.camera_applied;
  camera_gated_in_a_row_ = 0;
  last_pose_init_stamp_s_ = camera.stamp_s;
  base_ = ekf_.state();
  // IMU samples that arrived before the (late) first camera pose and are newer than it are kept.
  while (!history_.empty() && history_.front().stamp_s < camera.stamp_s) {
    history_.pop_front();
    ++counters_.imu_before_start;
  }
  for (Entry& e : history_) {
    Apply(e, true);
    e.after = ekf_.state();
  }
  Trim();
  return AddResult::kInitialized;
}

UpdateResult MeasurementBuffer::Apply(Entry& e, bool count) {
  // With the gyro and accelerometer switched off an IMU sample carries nothing:
  // like the thesis's measurement-driven EKF, the pose then freezes between
  // camera frames instead of extrapolating the last angular rate (7.3 survey).
  if (!e.is_camera && !config_.use_gyro && config_.accel_mode == AccelMode::kOff) return UpdateResult::kDisabled;
  // The gyro's rate over (previous stamp, e.stamp] drives the prediction over it.
  const bool gyro_centred = !e.is_camera && config_.gyro_is_centred_interval_mean;
  if (gyro_centred) {
    // The sample's period starts halfway from the previous sample (gaps over 0.1 s: at its stamp).
    const double previous = ekf_.state().last_imu_stamp_s;
    if (previous >= 0.0 && e.stamp_s > previous && e.stamp_s - previous <= 0.1)
      ekf_.Predict(0.5 * (previous + e.stamp_s));
    ekf_.NoteImuStamp(e.stamp_s);
  }
  const bool gyro_first = !e.is_camera && (config_.gyro_is_interval_mean || gyro_centred);
  const UpdateResult gyro = gyro_first ? ekf_.UpdateGyro(e.imu) : UpdateResult::kDisabled;
  ekf_.Predict(e.stamp_s);
  auto tally = [&](UpdateResult r, uint64_t* applied) {
    if (!count) return;
    if (r == UpdateResult::kApplied) ++*applied;
    if (r == UpdateResult::kGated) ++counters_.accel_gated;
    if (r == UpdateResult::kRejectedNonFinite) ++counters_.nan_rejected;
    if (r == UpdateResult::kNumericalFailure) ++counters_.numerical_failures;
  };
  if (e.is_cones) {
    ConeFrameResult res;
    // Re-acquiring, a lone cone may be any layout cone the drifted prediction lets through (README).
    const UpdateResult r = ekf_.UpdateCones(e.cones, &res, ReacquireDue() ? config_.reacquire_min_cones : 1);
    if (count) TallyCones(r, res);
    return r;
  }
  if (e.superseded) return UpdateResult::kDisabled;  // its image's cones were fused
  if (e.is_camera) {
    double nis = 0.0, gate_chi2 = 0.0;
    const UpdateResult r = ekf_.UpdateCamera(e.camera, &nis, &gate_chi2);
    if (count) e.counted = r;
    if (count && r == UpdateResult::kGated) {
      ++counters_.camera_gated;
      counters_.camera_gate_last_rejected_chi2 = gate_chi2;
      return r;
    }
    tally(r, &counters_.camera_applied);
    if (count && r == UpdateResult::kApplied) {
      ++counters_.camera_nis_count;
      counters_.camera_nis_sum += nis;
      counters_.camera_nis_last = nis;
    }
    return r;
  }
  tally(gyro_first ? gyro : ekf_.UpdateGyro(e.imu), &counters_.gyro_applied);
  tally(ekf_.UpdateAccel(e.imu), &counters_.accel_applied);
  return UpdateResult::kDisabled;
}

void MeasurementBuffer::TallyCones(UpdateResult r, const ConeFrameResult& res) {
  last_cone_frame_ = res;
  counters_.cones_applied += static_cast<uint64_t>(res.fused);
  counters_.cones_gated += static_cast<uint64_t>(res.gated);
  counters_.cones_joint_dropped += static_cast<uint64_t>(res.joint_dropped);
  counters_.cones_behind_camera += static_cast<uint64_t>(res.behind_camera);
  if (res.gated + res.joint_dropped + res.behind_camera > 0) counters_.cone_last_rejected_chi2 = res.worst_gate_chi2;
  if (res.repeated) ++counters_.cone_frames_repeated;
  if (r == UpdateResult::kApplied) {
    ++counters_.cone_frames_applied;
    ++counters_.cone_nis_count;
    counters_.cone_nis_sum += res.nis;
    counters_.cone_nis_dof += static_cast<uint64_t>(kConeDof * res.fused);
    counters_.cone_nis_last = res.nis;
  } else if (r == UpdateResult::kGated) {
    ++counters_.cone_frames_rejected;
    if (res.too_few > 0) ++counters_.cone_frames_too_few;
    if (res.ambiguous > 0) ++counters_.cone_frames_ambiguous;
  } else if (r == UpdateResult::kNumericalFailure) {
    ++counters_.numerical_failures;
  } else if (r == UpdateResult::kRejectedNonFinite) {
    ++counters_.nan_rejected;
  }
}

// Keeps what a measurement up to max_delay_s late needs: the entries inside the
// window, and as base_ the state just before them.
void MeasurementBuffer::Trim() {
  if (history_.empty()) return;
  const double oldest_kept = history_.back().stamp_s - config_.max_delay_s;
  while (!history_.empty() && history_.front().stamp_s < oldest_kept) {
    if (ekf_.initialized()) {
      base_ = history_.front().after;
    } else {
      ++counters_.imu_before_start;  // too old to follow the first camera pose
    }
    history_.pop_front();
  }
}

}  // namespace pose_ekf
