// EkfCore: configuration, initialisation, the time update and the state read-out. The measurement updates:
// ekf_camera_update.cpp, ekf_imu_update.cpp, cone_update.cpp, all through Update<M> (ekf_update.h).
#include "pose_ekf/core/ekf_core.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "ekf_update.h"
#include "pose_math/covariance.h"

namespace pose_ekf {

const char* ToString(UpdateResult r) {
  switch (r) {
    case UpdateResult::kApplied:
      return "applied";
    case UpdateResult::kDisabled:
      return "disabled";
    case UpdateResult::kGated:
      return "gated";
    case UpdateResult::kRejectedNonFinite:
      return "rejected (non-finite)";
    case UpdateResult::kNumericalFailure:
      return "numerical failure";
  }
  return "?";
}

EkfCore::EkfCore(const EkfConfig& config) { SetConfig(config); }

void EkfCore::SetConfig(const EkfConfig& config) {
  const std::string err = config.Validate();
  if (!err.empty()) throw std::invalid_argument("pose_ekf config: " + err);
  config_ = config;
  camera_gate_chi2_ =
      config_.camera_gate_chi2 > 0.0 ? config_.camera_gate_chi2 : std::numeric_limits<double>::infinity();
  SetConeGates();
  if (initialized_) {  // the state's layout takes effect at the next Initialize()
    config_.estimate_gyro_bias = has_gyro_bias_;
    config_.estimate_accel_bias = has_accel_bias_;
  }
}

bool EkfCore::Initialize(const CameraMeasurement& m) {
  if (!PoseUsable(m) || !std::isfinite(m.stamp_s)) return false;
  const int n = StateSize(config_);
  has_gyro_bias_ = config_.estimate_gyro_bias;
  has_accel_bias_ = config_.estimate_accel_bias;
  s_.stamp_s = m.stamp_s;
  s_.x = StateVector::Zero(n);
  s_.last_gyro_stamp_s = s_.last_imu_stamp_s = -1.0;
  s_.alpha_camera_rad_s2.setZero();
  s_.x.segment<4>(kQ) = m.T_cones_camera.q.normalized();
  s_.x.segment<3>(kP) = m.T_cones_camera.t;
  s_.P = StateMatrix::Zero(n, n);
  s_.P.block<4, 4>(kQ, kQ) = m.cov.topLeftCorner<4, 4>();
  s_.P.block<4, 3>(kQ, kP) = m.cov.topRightCorner<4, 3>();
  s_.P.block<3, 4>(kP, kQ) = m.cov.bottomLeftCorner<3, 4>();
  s_.P.block<3, 3>(kP, kP) = m.cov.bottomRightCorner<3, 3>();
  InitializeUnmeasured(n);
  pose_math::SymmetrizeCovariance(s_.P);
  initialized_ = true;
  return true;
}

void EkfCore::InitializeUnmeasured(int n) {
  s_.omega_walk_pending_s = 0.0;  // P(ω) starts from init_sigma_omega_rad_s
  s_.fused_view = FusedConeView{};
  auto set_diag = [&](int i, double sigma) { s_.P.block<3, 3>(i, i) = sigma * sigma * Eigen::Matrix3d::Identity(); };
  set_diag(kW, config_.init_sigma_omega_rad_s);
  set_diag(kV, config_.init_sigma_v_m_s);
  set_diag(kA, config_.init_sigma_a_m_s2);
  if (config_.estimate_gyro_bias) set_diag(kB, config_.init_sigma_gyro_bias_rad_s);
  if (config_.estimate_accel_bias) set_diag(AccelBiasIndex(config_), config_.init_sigma_accel_bias_m_s2);
  (void)n;
}

bool EkfCore::InitializeFromGravity(double stamp_s, const Eigen::Vector3d& f) {
  if (!f.allFinite() || !std::isfinite(stamp_s) || f.norm() < 1e-3) return false;
  if (config_.accel_gate_m_s2 > 0.0 && std::abs(f.norm() - config_.gravity_m_s2) > config_.accel_gate_m_s2) {
    return false;  // moving: wait for a sample that measures gravity only (5.34)
  }
  // R(q) f/|f| = e_z: the specific force points up in the cones frame.
  const pose_math::Quat q =
      pose_math::ThesisFromEigen(Eigen::Quaterniond::FromTwoVectors(f.normalized(), Eigen::Vector3d::UnitZ()));
  const int n = StateSize(config_);
  has_gyro_bias_ = config_.estimate_gyro_bias;
  has_accel_bias_ = config_.estimate_accel_bias;
  s_.stamp_s = stamp_s;
  s_.x = StateVector::Zero(n);
  s_.last_gyro_stamp_s = s_.last_imu_stamp_s = -1.0;
  s_.alpha_camera_rad_s2.setZero();
  s_.x.segment<4>(kQ) = q;
  s_.P = StateMatrix::Zero(n, n);
  // Fixed-axis (cones frame) perturbation: small tilt about x, y; heading about z unknown.
  const Eigen::Matrix<double, 4, 3> G = pose_math::RotationPerturbationToQuat(q);
  const Eigen::Vector3d var(config_.init_sigma_tilt_rad * config_.init_sigma_tilt_rad,
                            config_.init_sigma_tilt_rad * config_.init_sigma_tilt_rad,
                            config_.init_sigma_heading_rad * config_.init_sigma_heading_rad);
  s_.P.block<4, 4>(kQ, kQ) = G * var.asDiagonal() * G.transpose();
  s_.P.block<3, 3>(kP, kP) = config_.init_sigma_p_m * config_.init_sigma_p_m * Eigen::Matrix3d::Identity();
  InitializeUnmeasured(n);
  pose_math::SymmetrizeCovariance(s_.P);
  initialized_ = true;
  return true;
}

void EkfCore::Predict(double stamp_s) {
  if (!initialized_ || !(stamp_s > s_.stamp_s)) return;
  const double dt = stamp_s - s_.stamp_s;
  const int steps = std::max(1, static_cast<int>(std::ceil(dt / config_.max_predict_step_s - 1e-9)));
  for (int i = 0; i < steps; ++i) PredictStep(dt / steps);
  s_.stamp_s = stamp_s;
}

void EkfCore::PredictStep(double dt) {
  const double tau_v = config_.velocity_time_constant_s, tau_a = config_.accel_time_constant_s;
  const StateMatrix F = TransitionJacobian(s_.x, dt, config_.quat_integration, tau_v, tau_a);  // (5.22)
  s_.x = PropagateState(s_.x, dt, config_.quat_integration, tau_v, tau_a);                     // (5.20)
  NormalizeQuat(s_.x);
  StateMatrix Q = ProcessNoise(config_, static_cast<int>(s_.x.size()), dt);  // (5.23)
  if (config_.omega_walk_at_gyro && config_.use_gyro) {  // ω's walk waits for the next gyro sample (config.h)
    Q.block<3, 3>(kW, kW).setZero();
    s_.omega_walk_pending_s += dt;
    if (s_.omega_walk_pending_s > kMaxOmegaWalkDeferS) AddOmegaWalk();
  }
  s_.P = PropagateCovariance(F, s_.P) + Q;  // (5.14)
  pose_math::SymmetrizeCovariance(s_.P);
}

void EkfCore::AddOmegaWalk() {
  const double s = config_.sigma_omega_rad_s_per_sqrt_s;
  s_.P.block<3, 3>(kW, kW).diagonal().array() += s * s * s_.omega_walk_pending_s;  // (5.23), ω's block
  s_.omega_walk_pending_s = 0.0;
}

pose_math::PoseWithCovariance EkfCore::Pose() const {
  pose_math::PoseWithCovariance out;
  if (!initialized_) return out;
  out.pose.q = s_.x.segment<4>(kQ);
  out.pose.t = s_.x.segment<3>(kP);
  out.cov.topLeftCorner<4, 4>() = s_.P.block<4, 4>(kQ, kQ);
  out.cov.topRightCorner<4, 3>() = s_.P.block<4, 3>(kQ, kP);
  out.cov.bottomLeftCorner<3, 4>() = s_.P.block<3, 4>(kP, kQ);
  out.cov.bottomRightCorner<3, 3>() = s_.P.block<3, 3>(kP, kP);
  return out;
}

Eigen::Vector3d EkfCore::gyro_bias_rad_s() const {
  if (!initialized_ || !has_gyro_bias_) return Eigen::Vector3d::Zero();
  return s_.x.segment<3>(kB);
}

Eigen::Vector3d EkfCore::accel_bias_m_s2() const {
  if (!initialized_ || !has_accel_bias_) return Eigen::Vector3d::Zero();
  return s_.x.segment<3>(AccelBiasIndex(config_));
}

}  // namespace pose_ekf
