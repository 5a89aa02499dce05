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

}  // namespace

StateVector PropagateState(const StateVector& x, double dt, QuatIntegration integration) {
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
  // Constant-acceleration translation (5.19); ω, a (and b) are random walks.
  y.segment<3>(kP) = x.segment<3>(kP) + dt * x.segment<3>(kV) + 0.5 * dt * dt * x.segment<3>(kA);
  y.segment<3>(kV) = x.segment<3>(kV) + dt * x.segment<3>(kA);
  return y;
}

StateMatrix TransitionJacobian(const StateVector& x, double dt, QuatIntegration integration) {
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
  F.block<3, 3>(kV, kA) = dt * Eigen::Matrix3d::Identity();
  return F;
}

StateMatrix ProcessNoise(const EkfConfig& c, int n, double dt) {
  StateVector d(n);
  d.segment<4>(kQ).setConstant(c.sigma_q_per_sqrt_s * c.sigma_q_per_sqrt_s);
  d.segment<3>(kW).setConstant(c.sigma_omega_rad_s_per_sqrt_s * c.sigma_omega_rad_s_per_sqrt_s);
  d.segment<3>(kP).setConstant(c.sigma_p_m_per_sqrt_s * c.sigma_p_m_per_sqrt_s);
  d.segment<3>(kV).setConstant(c.sigma_v_m_s_per_sqrt_s * c.sigma_v_m_s_per_sqrt_s);
  d.segment<3>(kA).setConstant(c.sigma_a_m_s2_per_sqrt_s * c.sigma_a_m_s2_per_sqrt_s);
  if (n > kBaseStates) {
    d.segment<3>(kB).setConstant(c.sigma_gyro_bias_rad_s_per_sqrt_s * c.sigma_gyro_bias_rad_s_per_sqrt_s);
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

}  // namespace pose_ekf
