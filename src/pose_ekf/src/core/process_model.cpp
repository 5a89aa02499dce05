#include "pose_ekf/core/process_model.h"

#include <cmath>

#include "pose_math/quaternion.h"

namespace pose_ekf {
namespace {

using pose_math::Quat;

// Coefficients of the exact update (2.71): g = c q + s QR(Ω) q with c = cos(|ω|dt/2),
// s = sin(|ω|dt/2)/|ω|, and ds_dn_over_n = (ds/d|ω|)/|ω| for the Jacobian.
struct ExactCoefficients {
  double c, s, ds_dn_over_n;
};

ExactCoefficients Exact(const Eigen::Vector3d& w, double dt) {
  const double n = w.norm();
  const double h = 0.5 * dt;
  const double x = n * h;
  if (x < 1e-4) {  // series: avoids 0/0; the next terms are O(x^4) relative
    return {1.0 - 0.5 * x * x, h * (1.0 - x * x / 6.0), -h * h * h / 3.0};
  }
  const double s = std::sin(x) / n;
  return {std::cos(x), s, (x * std::cos(x) - std::sin(x)) / (n * n * n)};
}

// Vector part of QL(q): the 4×3 map ω -> q ⊗ [0 ω].
Eigen::Matrix<double, 4, 3> LeftVectorPart(const Quat& q) { return pose_math::LeftMatrix(q).rightCols<3>(); }

// R(q)ᵀ v and its derivative for the general R of (2.36): Rᵀ(q) = R(q*).
Eigen::Vector3d RotateInverse(const Quat& q, const Eigen::Vector3d& v) {
  const double q0 = q[0];
  const Eigen::Vector3d qv = -q.tail<3>();
  return (q0 * q0 - qv.squaredNorm()) * v + 2.0 * qv.dot(v) * qv + 2.0 * q0 * qv.cross(v);
}

Eigen::Matrix<double, 3, 4> RotateInverseJacobian(const Quat& q, const Eigen::Vector3d& v) {
  const Quat qc(q[0], -q[1], -q[2], -q[3]);
  Eigen::Matrix<double, 3, 4> J = pose_math::RotateJacobianWrtQuat(qc, v);
  J.rightCols<3>() *= -1.0;  // chain rule through q* = diag(1,-1,-1,-1) q
  return J;
}

// exp(-dt/τ), 1 for τ <= 0 (no damping).
double Decay(double dt, double tau) { return tau > 0.0 ? std::exp(-dt / tau) : 1.0; }

// [v]× with [v]× u = v × u.
Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

}  // namespace

StateVector PropagateState(const StateVector& x, double dt, QuatIntegration integration, double tau_v, double tau_a) {
  StateVector y = x;
  const Quat q = x.segment<4>(kQ);
  const Eigen::Vector3d w = x.segment<3>(kW);
  const Eigen::Vector4d q_dot_dir = LeftVectorPart(q) * w;  // QR(Ω) q = q ⊗ [0 ω]
  if (integration == QuatIntegration::kFirstOrder) {
    y.segment<4>(kQ) = q + 0.5 * dt * q_dot_dir;  // (5.21) (2.70)
  } else {
    const ExactCoefficients e = Exact(w, dt);
    y.segment<4>(kQ) = e.c * q + e.s * q_dot_dir;  // (2.71)
  }
  // Constant-acceleration translation (5.19); ω, a (and b) are random walks;
  // v and a optionally decay towards 0 (a hand that stops).
  y.segment<3>(kP) = x.segment<3>(kP) + dt * x.segment<3>(kV) + 0.5 * dt * dt * x.segment<3>(kA);
  y.segment<3>(kV) = Decay(dt, tau_v) * (x.segment<3>(kV) + dt * x.segment<3>(kA));
  y.segment<3>(kA) = Decay(dt, tau_a) * x.segment<3>(kA);
  return y;
}

StateMatrix TransitionJacobian(const StateVector& x, double dt, QuatIntegration integration, double tau_v,
                               double tau_a) {
  const int n = static_cast<int>(x.size());
  StateMatrix F = StateMatrix::Identity(n, n);  // (5.22)
  const Quat q = x.segment<4>(kQ);
  const Eigen::Vector3d w = x.segment<3>(kW);
  const Eigen::Matrix<double, 4, 3> L = LeftVectorPart(q);
  if (integration == QuatIntegration::kFirstOrder) {
    F.block<4, 4>(kQ, kQ) += 0.5 * dt * pose_math::OmegaMatrix(w);
    F.block<4, 3>(kQ, kW) = 0.5 * dt * L;
  } else {
    const ExactCoefficients e = Exact(w, dt);
    const Eigen::Vector4d q_dot_dir = L * w;
    F.block<4, 4>(kQ, kQ) = e.c * Eigen::Matrix4d::Identity() + e.s * pose_math::OmegaMatrix(w);
    // ∂c/∂ω = -(dt/2) s ω, ∂s/∂ω = ds_dn_over_n ω.
    F.block<4, 3>(kQ, kW) =
        q * (-0.5 * dt * e.s * w.transpose()) + q_dot_dir * (e.ds_dn_over_n * w.transpose()) + e.s * L;
  }
  F.block<3, 3>(kP, kV) = dt * Eigen::Matrix3d::Identity();
  F.block<3, 3>(kP, kA) = 0.5 * dt * dt * Eigen::Matrix3d::Identity();
  const double dv = Decay(dt, tau_v);
  F.block<3, 3>(kV, kV) = dv * Eigen::Matrix3d::Identity();
  F.block<3, 3>(kV, kA) = dv * dt * Eigen::Matrix3d::Identity();
  F.block<3, 3>(kA, kA) = Decay(dt, tau_a) * Eigen::Matrix3d::Identity();
  return F;
}

StateMatrix PropagateCovariance(const StateMatrix& F, const StateMatrix& P) {
  constexpr int kQW = kP - kQ, kPVA = kB - kP;  // q and ω; p, v and a
  const auto Fq = F.block<4, kQW>(kQ, kQ);
  const auto Fpva = F.block<kPVA, kPVA>(kP, kP);
  StateMatrix M = P;  // F P: only the rows of q and of p, v, a change
  M.middleRows<4>(kQ) = Fq * P.topRows<kQW>();
  M.middleRows<kPVA>(kP) = Fpva * P.middleRows<kPVA>(kP);
  StateMatrix out = M;  // (F P) Fᵀ: the same columns
  out.middleCols<4>(kQ) = M.leftCols<kQW>() * Fq.transpose();
  out.middleCols<kPVA>(kP) = M.middleCols<kPVA>(kP) * Fpva.transpose();
  return out;
}

StateMatrix ProcessNoise(const EkfConfig& c, int n, double dt) {
  StateVector d(n);
  d.segment<4>(kQ).setConstant(c.sigma_q_per_sqrt_s * c.sigma_q_per_sqrt_s);
  d.segment<3>(kW).setConstant(c.sigma_omega_rad_s_per_sqrt_s * c.sigma_omega_rad_s_per_sqrt_s);
  d.segment<3>(kP).setConstant(c.sigma_p_m_per_sqrt_s * c.sigma_p_m_per_sqrt_s);
  d.segment<3>(kV).setConstant(c.sigma_v_m_s_per_sqrt_s * c.sigma_v_m_s_per_sqrt_s);
  d.segment<3>(kA).setConstant(c.sigma_a_m_s2_per_sqrt_s * c.sigma_a_m_s2_per_sqrt_s);
  if (c.estimate_gyro_bias && n >= kB + 3) {
    d.segment<3>(kB).setConstant(c.sigma_gyro_bias_rad_s_per_sqrt_s * c.sigma_gyro_bias_rad_s_per_sqrt_s);
  }
  const int ba = AccelBiasIndex(c);
  if (ba >= 0 && n >= ba + 3) {
    d.segment<3>(ba).setConstant(c.sigma_accel_bias_m_s2_per_sqrt_s * c.sigma_accel_bias_m_s2_per_sqrt_s);
  }
  return (dt * d).asDiagonal();  // (5.23)
}

Eigen::Vector3d AccelModel(const StateVector& x, double g, AccelMode mode) {
  Eigen::Vector3d v(0.0, 0.0, g);
  if (mode == AccelMode::kPositionAndOrientation) v += x.segment<3>(kA);  // (5.39)
  return RotateInverse(x.segment<4>(kQ), v);                              // (5.36)
}

Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxStates> AccelJacobian(const StateVector& x, double g,
                                                                         AccelMode mode) {
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxStates> H = Eigen::MatrixXd::Zero(3, x.size());
  Eigen::Vector3d v(0.0, 0.0, g);
  if (mode == AccelMode::kPositionAndOrientation) {
    v += x.segment<3>(kA);
    // ∂(R(q)ᵀ a)/∂a = R(q)ᵀ (5.40), column by column from the same general form.
    for (int i = 0; i < 3; ++i) H.col(kA + i) = RotateInverse(x.segment<4>(kQ), Eigen::Vector3d::Unit(i));
  }
  H.block<3, 4>(0, kQ) = RotateInverseJacobian(x.segment<4>(kQ), v);  // (5.37)
  return H;
}

Eigen::Vector3d AccelModel(const StateVector& x, double g, AccelMode mode, const Eigen::Vector3d& r, int ba) {
  const Eigen::Vector3d w = x.segment<3>(kW);
  Eigen::Vector3d h = AccelModel(x, g, mode) + w.cross(w.cross(r));  // centripetal at the IMU
  if (ba >= 0) h += x.segment<3>(ba);
  return h;
}

Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxStates> AccelJacobian(const StateVector& x, double g, AccelMode mode,
                                                                         const Eigen::Vector3d& r, int ba) {
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxStates> H = AccelJacobian(x, g, mode);
  const Eigen::Vector3d w = x.segment<3>(kW);
  // ω×(ω×r) = ω (ω·r) - r |ω|²: derivative ω rᵀ + (ω·r) I - 2 r ωᵀ.
  H.block<3, 3>(0, kW) += w * r.transpose() + w.dot(r) * Eigen::Matrix3d::Identity() - 2.0 * r * w.transpose();
  if (ba >= 0) H.block<3, 3>(0, ba).setIdentity();
  return H;
}

Eigen::Matrix3d AccelLeverArmNoise(const Eigen::Vector3d& r, double sigma) {
  const Eigen::Matrix3d S = Skew(r);  // α×r = -[r]× α
  return sigma * sigma * S * S.transpose();
}

}  // namespace pose_ekf
