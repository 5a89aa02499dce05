#include "pose_math/quaternion.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace pose_math {

Quat ThesisFromEigen(const Eigen::Quaterniond& q) { return Quat(q.w(), q.x(), q.y(), q.z()); }

Eigen::Quaterniond EigenFromThesis(const Quat& q) { return Eigen::Quaterniond(q[0], q[1], q[2], q[3]); }

Quat NormalizedQuat(const Quat& q, const char* what) {
  if (!q.allFinite()) {
    throw std::invalid_argument(std::string(what) + ": quaternion has a non-finite coefficient");
  }
  const double n2 = q.squaredNorm();
  // Already unit to rounding: skip the sqrt and divide (the common case).
  if (std::abs(n2 - 1.0) <= 4.0 * std::numeric_limits<double>::epsilon()) return q;
  if (n2 < kMinQuaternionNorm * kMinQuaternionNorm) {
    throw std::invalid_argument(std::string(what) + ": quaternion norm is zero");
  }
  return q / std::sqrt(n2);
}

Quat Conjugate(const Quat& q) { return Quat(q[0], -q[1], -q[2], -q[3]); }  // (2.32)

Quat CanonicalSign(const Quat& q) { return q[0] < 0.0 ? Quat(-q) : q; }

Eigen::Matrix4d LeftMatrix(const Quat& p) {
  Eigen::Matrix4d m;  // QL(p) (2.44)
  // clang-format off
  m << p[0], -p[1], -p[2], -p[3],
       p[1],  p[0], -p[3],  p[2],
       p[2],  p[3],  p[0], -p[1],
       p[3], -p[2],  p[1],  p[0];
  // clang-format on
  return m;
}

Eigen::Matrix4d RightMatrix(const Quat& q) {
  Eigen::Matrix4d m;  // QR(q) (2.44)
  // clang-format off
  m << q[0], -q[1], -q[2], -q[3],
       q[1],  q[0],  q[3], -q[2],
       q[2], -q[3],  q[0],  q[1],
       q[3],  q[2], -q[1],  q[0];
  // clang-format on
  return m;
}

Quat Multiply(const Quat& p, const Quat& q) { return LeftMatrix(p) * q; }  // p ⊗ q = QL(p) q (2.44)

Eigen::Matrix3d Skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d s;  // (2.50)
  // clang-format off
  s <<   0.0, -w.z(),  w.y(),
       w.z(),    0.0, -w.x(),
      -w.y(),  w.x(),    0.0;
  // clang-format on
  return s;
}

Eigen::Matrix4d OmegaMatrix(const Eigen::Vector3d& omega_body_rad_s) {
  return RightMatrix(Quat(0.0, omega_body_rad_s.x(), omega_body_rad_s.y(), omega_body_rad_s.z()));  // (2.69)
}

namespace {
void CheckOmegaDt(const Eigen::Vector3d& omega, double dt, const char* what) {
  if (!omega.allFinite() || !std::isfinite(dt)) {
    throw std::invalid_argument(std::string(what) + ": non-finite angular velocity or time step");
  }
}
}  // namespace

Quat IntegrateFirstOrder(const Quat& q, const Eigen::Vector3d& omega_body_rad_s, double dt_s) {
  CheckOmegaDt(omega_body_rad_s, dt_s, "IntegrateFirstOrder");
  const Quat qn = NormalizedQuat(q, "IntegrateFirstOrder");
  return NormalizedQuat(qn + 0.5 * dt_s * OmegaMatrix(omega_body_rad_s) * qn, "IntegrateFirstOrder");  // (2.70)
}

Quat IntegrateExact(const Quat& q, const Eigen::Vector3d& omega_body_rad_s, double dt_s) {
  CheckOmegaDt(omega_body_rad_s, dt_s, "IntegrateExact");
  const Quat qn = NormalizedQuat(q, "IntegrateExact");
  const double w = omega_body_rad_s.norm();
  const double half_angle = 0.5 * w * dt_s;
  // sin(|ω|dt/2)/|ω| → dt/2 as |ω| → 0; the series keeps full precision there.
  const double sin_over_w =
      half_angle < 1e-4 ? 0.5 * dt_s * (1.0 - half_angle * half_angle / 6.0) : std::sin(half_angle) / w;
  const Quat out = std::cos(half_angle) * qn + sin_over_w * (OmegaMatrix(omega_body_rad_s) * qn);  // (2.71)
  return NormalizedQuat(out, "IntegrateExact");
}

Eigen::Vector3d Rotate(const Quat& q, const Eigen::Vector3d& v) {
  const Quat qn = NormalizedQuat(q, "Rotate");
  const double q0 = qn[0];
  const Eigen::Vector3d qv = qn.tail<3>();
  // Vector part of q ⊗ [0 v] ⊗ q*, expanded (2.42).
  return (q0 * q0 - qv.squaredNorm()) * v + 2.0 * qv.dot(v) * qv + 2.0 * q0 * qv.cross(v);
}

Eigen::Matrix<double, 3, 4> RotateJacobianWrtQuat(const Quat& q, const Eigen::Vector3d& v) {
  // R(q) v = (q0² − |q⃗|²) v + 2 (q⃗·v) q⃗ + 2 q0 q⃗ × v  for the general R of (2.36).
  const double q0 = q[0];
  const Eigen::Vector3d qv = q.tail<3>();
  Eigen::Matrix<double, 3, 4> J;
  J.col(0) = 2.0 * q0 * v + 2.0 * qv.cross(v);
  J.rightCols<3>() = -2.0 * v * qv.transpose() + 2.0 * qv.dot(v) * Eigen::Matrix3d::Identity() +
                     2.0 * qv * v.transpose() - 2.0 * q0 * Skew(v);
  return J;
}

}  // namespace pose_math
