// EkfCore::UpdateGyro (5.27)-(5.29) and UpdateAccel (5.30)-(5.39), with the lever arm's angular
// acceleration, and UpdateStill. Update<3> is instantiated here (ekf_update.h).
#include <cmath>

#include "ekf_update.h"
#include "pose_ekf/core/ekf_core.h"

namespace pose_ekf {

UpdateResult EkfCore::UpdateGyro(const ImuMeasurement& m, double* nis) {
  if (!config_.use_gyro || !m.has_gyro) return UpdateResult::kDisabled;
  if (!m.omega_camera_rad_s.allFinite() || (m.has_covariance && !m.gyro_cov.allFinite())) {
    return UpdateResult::kRejectedNonFinite;
  }
  if (s_.omega_walk_pending_s > 0.0) AddOmegaWalk();  // omega_walk_at_gyro: the walk since the last sample
  const int n = static_cast<int>(s_.x.size());
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxStates> H = Eigen::MatrixXd::Zero(3, n);
  H.block<3, 3>(0, kW).setIdentity();       // (5.29)
  Eigen::Vector3d h = s_.x.segment<3>(kW);  // (5.28)
  if (has_gyro_bias_) {
    H.block<3, 3>(0, kB).setIdentity();  // z = ω + b
    h += s_.x.segment<3>(kB);
  }
  const Eigen::Matrix3d R =
      (config_.use_message_imu_covariance && m.has_covariance)
          ? m.gyro_cov
          : Eigen::Matrix3d(config_.sigma_gyro_rad_s * config_.sigma_gyro_rad_s * Eigen::Matrix3d::Identity());
  const Eigen::Vector3d y = m.omega_camera_rad_s - h;  // (5.27)
  const UpdateResult result = Update<3>(y, H, R, nis);
  if (result == UpdateResult::kApplied) NoteAngularAcceleration();
  return result;
}

// z = 0 for the velocity and the angular rate (beyond the thesis): pseudo-measurements of a still camera, z - h = -v
// and -ω, H = [0 I 0] for each. ω = 0 also lets the gyro's next sample show its bias.
UpdateResult EkfCore::UpdateStill(double sigma_v_m_s, double sigma_omega_rad_s) {
  if (!initialized_ || !(sigma_v_m_s > 0.0) || !(sigma_omega_rad_s > 0.0)) return UpdateResult::kDisabled;
  const int n = static_cast<int>(s_.x.size());
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxStates> H = Eigen::MatrixXd::Zero(3, n);
  H.block<3, 3>(0, kV).setIdentity();
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const UpdateResult v = Update<3>(-s_.x.segment<3>(kV), H, Eigen::Matrix3d(sigma_v_m_s * sigma_v_m_s * I), nullptr);
  if (v != UpdateResult::kApplied) return v;
  H.setZero();
  H.block<3, 3>(0, kW).setIdentity();
  return Update<3>(-s_.x.segment<3>(kW), H, Eigen::Matrix3d(sigma_omega_rad_s * sigma_omega_rad_s * I), nullptr);
}

UpdateResult EkfCore::UpdateAccel(const ImuMeasurement& m, double* nis) {
  if (config_.accel_mode == AccelMode::kOff || !m.has_accel) return UpdateResult::kDisabled;
  if (!m.accel_camera_m_s2.allFinite() || !m.p_imu_in_camera_m.allFinite() ||
      (m.has_covariance && !m.accel_cov.allFinite())) {
    return UpdateResult::kRejectedNonFinite;
  }
  const Eigen::Vector3d r = config_.model_lever_arm ? m.p_imu_in_camera_m : Eigen::Vector3d::Zero();
  const int ba = has_accel_bias_ ? AccelBiasIndex(config_) : -1;
  // z (5.30) - h(x): (5.36) for orientation only, (5.39) with acceleration, plus
  // the lever arm's centripetal term and the bias.
  Eigen::Vector3d h = AccelModel(s_.x, config_.gravity_m_s2, config_.accel_mode, r, ba);
  if (config_.alpha_from_gyro) h += s_.alpha_camera_rad_s2.cross(r);  // α an input, not a state
  // Human motion: use the accelerometer only while it measures about g (5.34),
  // once the modelled lever-arm and bias terms are taken out.
  if (config_.accel_gate_m_s2 > 0.0) {
    const Eigen::Vector3d f = m.accel_camera_m_s2 - (h - AccelModel(s_.x, config_.gravity_m_s2, config_.accel_mode));
    if (std::abs(f.norm() - config_.gravity_m_s2) > config_.accel_gate_m_s2) return UpdateResult::kGated;
  }
  const Eigen::Vector3d y = m.accel_camera_m_s2 - h;
  const auto H = AccelJacobian(s_.x, config_.gravity_m_s2, config_.accel_mode, r, ba);
  Eigen::Matrix3d R =
      (config_.use_message_imu_covariance && m.has_covariance)
          ? m.accel_cov
          : Eigen::Matrix3d(config_.sigma_accel_m_s2 * config_.sigma_accel_m_s2 * Eigen::Matrix3d::Identity());
  if (config_.model_lever_arm) R += AccelLeverArmNoise(r, config_.sigma_angular_accel_rad_s2);  // α×r
  return Update<3>(y, H, R, nis);
}

// α for the lever arm: the change of the estimated ω over the last gyro period
// (longer gaps than 0.1 s, or none yet: α = 0).
void EkfCore::NoteAngularAcceleration() {
  const Eigen::Vector3d w = s_.x.segment<3>(kW);
  const double dt = s_.stamp_s - s_.last_gyro_stamp_s;
  s_.alpha_camera_rad_s2 = (s_.last_gyro_stamp_s >= 0.0 && dt > 1e-4 && dt <= 0.1)
                               ? Eigen::Vector3d((w - s_.omega_at_last_gyro_rad_s) / dt)
                               : Eigen::Vector3d::Zero();
  s_.omega_at_last_gyro_rad_s = w;
  s_.last_gyro_stamp_s = s_.stamp_s;
}

}  // namespace pose_ekf
