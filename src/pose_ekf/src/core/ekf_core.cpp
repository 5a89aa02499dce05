#include "pose_ekf/core/ekf_core.h"

#include "pose_math/covariance.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pose_ekf {
namespace {

// The camera covariance lives on the tangent plane of the unit sphere (5.6.4)
// and has no variance along q itself. A tiny radial variance keeps S well
// conditioned; the radial residual is O(angle²) and normalisation (5.41)
// removes whatever it does to the state.
constexpr double kCameraRadialVariance = 1e-10;

void NormalizeQuat(StateVector& x) { x.segment<4>(kQ).normalize(); }  // (5.41)

// The camera gate's statistic: yᵀ S⁻¹ y for the innovation y and its
// covariance S that the update uses, on the 6 dof a pose has. The quaternion
// rows are taken on the plane tangent to the unit sphere at the prediction
// (the plane R lives on, 5.6.4): along q itself y is only the O(angle²) gap
// between two unit quaternions and S only kCameraRadialVariance, so the 7-dof
// yᵀ S⁻¹ y would grow with the fourth power of a rotation error of a few
// degrees. The statistic does not depend on the basis of the plane. NaN when
// S is not positive definite there.
double CameraGateStatistic(const Eigen::Matrix<double, 7, 1>& y, const Eigen::Matrix<double, 7, 7>& S,
                           const pose_math::Quat& q_pred) {
  Eigen::Matrix<double, 6, 7> T = Eigen::Matrix<double, 6, 7>::Zero();
  T.topLeftCorner<3, 4>() = pose_math::RotationPerturbationToQuat(q_pred).transpose();
  T.bottomRightCorner<3, 3>().setIdentity();
  const Eigen::Matrix<double, 6, 1> y6 = T * y;
  const Eigen::Matrix<double, 6, 6> S6 = T * S * T.transpose();
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(S6);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return y6.dot(ldlt.solve(y6));
}

}  // namespace

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
  s_.P = F * s_.P * F.transpose() + ProcessNoise(config_, static_cast<int>(s_.x.size()), dt);  // (5.14)
  pose_math::SymmetrizeCovariance(s_.P);
}

template <int M>
UpdateResult EkfCore::Update(const Eigen::Matrix<double, M, 1>& residual,
                             const Eigen::Matrix<double, M, Eigen::Dynamic, 0, M, kMaxStates>& H,
                             const Eigen::Matrix<double, M, M>& R, double* nis) {
  using MatNM = Eigen::Matrix<double, Eigen::Dynamic, M, 0, kMaxStates, M>;
  const int n = static_cast<int>(s_.x.size());
  const MatNM PHt = s_.P * H.transpose();
  Eigen::Matrix<double, M, M> S = H * PHt + R;
  S = 0.5 * (S + S.transpose()).eval();
  const Eigen::LDLT<Eigen::Matrix<double, M, M>> ldlt(S);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || !(ldlt.vectorD().minCoeff() > 0.0)) {
    return UpdateResult::kNumericalFailure;
  }
  const MatNM K = ldlt.solve(PHt.transpose()).transpose();  // (5.15)
  StateVector x = s_.x + K * residual;                      // (5.16)
  StateMatrix P(n, n);
  if (config_.joseph_update) {
    StateMatrix IKH = StateMatrix::Identity(n, n) - K * H;
    P = IKH * s_.P * IKH.transpose() + K * R * K.transpose();  // Joseph form of (5.17)
  } else {
    P = s_.P - K * PHt.transpose();  // (I - K H) P (5.17), with H P = (P Hᵀ)ᵀ
  }
  pose_math::SymmetrizeCovariance(P);
  NormalizeQuat(x);  // (5.41)
  if (!x.allFinite() || !P.allFinite()) return UpdateResult::kNumericalFailure;
  if (nis) *nis = residual.dot(ldlt.solve(residual));
  s_.x = x;
  s_.P = P;
  return UpdateResult::kApplied;
}

// The per-cone update (cone_update.cpp) uses the same update.
template UpdateResult EkfCore::Update<kConeDof>(const ConeVector&, const ConeJacobian&, const ConeMatrix&, double*);

UpdateResult EkfCore::UpdateCamera(const CameraMeasurement& m, double* nis, double* gate_chi2) {
  if (!config_.use_camera) return UpdateResult::kDisabled;
  if (!PoseUsable(m)) return UpdateResult::kRejectedNonFinite;
  const int n = static_cast<int>(s_.x.size());
  Eigen::Vector4d z_q = m.T_cones_camera.q.normalized();
  const Eigen::Vector4d q_pred = s_.x.segment<4>(kQ);
  if ((q_pred - z_q).norm() > (q_pred + z_q).norm()) z_q = -z_q;  // mirrored quaternion (5.5.1)
  Eigen::Matrix<double, 7, 1> y;
  y << z_q - q_pred, m.T_cones_camera.t - s_.x.segment<3>(kP);  // z (5.24) - H x (5.25)
  Eigen::Matrix<double, 7, Eigen::Dynamic, 0, 7, kMaxStates> H = Eigen::MatrixXd::Zero(7, n);
  H.block<4, 4>(0, kQ).setIdentity();  // (5.26)
  H.block<3, 3>(4, kP).setIdentity();
  Eigen::Matrix<double, 7, 7> R = m.cov;
  R.topLeftCorner<4, 4>() += kCameraRadialVariance * z_q * z_q.transpose();
  if (gate_chi2 || std::isfinite(camera_gate_chi2_)) {
    Eigen::Matrix<double, 7, 7> S = H * s_.P * H.transpose() + R;  // the S of (5.15)
    S = 0.5 * (S + S.transpose()).eval();
    const double d2 = CameraGateStatistic(y, S, q_pred);
    if (gate_chi2) *gate_chi2 = d2;
    if (std::isfinite(camera_gate_chi2_)) {
      if (std::isnan(d2)) return UpdateResult::kNumericalFailure;
      if (d2 > camera_gate_chi2_) return UpdateResult::kGated;
    }
  }
  return Update<7>(y, H, R, nis);
}

UpdateResult EkfCore::UpdateGyro(const ImuMeasurement& m, double* nis) {
  if (!config_.use_gyro || !m.has_gyro) return UpdateResult::kDisabled;
  if (!m.omega_camera_rad_s.allFinite() || (m.has_covariance && !m.gyro_cov.allFinite())) {
    return UpdateResult::kRejectedNonFinite;
  }
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
