#include "pose_math/rotation.h"

#include <Eigen/SVD>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pose_math {

namespace {
void CheckFinite(const Eigen::Matrix3d& R, const char* what) {
  if (!R.allFinite()) {
    throw std::invalid_argument(std::string(what) + ": matrix has a non-finite entry");
  }
}

// (R − Rᵀ) / 2 as a vector: sin θ k (2.24) (2.25).
Eigen::Vector3d AntisymmetricPart(const Eigen::Matrix3d& R) {
  return 0.5 * Eigen::Vector3d(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
}
}  // namespace

Eigen::Matrix3d RotationFromQuat(const Quat& q) {
  const Quat u = NormalizedQuat(q, "RotationFromQuat");
  const double q0 = u[0], qx = u[1], qy = u[2], qz = u[3];
  Eigen::Matrix3d R;
  // clang-format off
  R << 1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - q0 * qz),     2 * (qx * qz + q0 * qy),
       2 * (qx * qy + q0 * qz),     1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - q0 * qx),
       2 * (qx * qz - q0 * qy),     2 * (qy * qz + q0 * qx),     1 - 2 * (qx * qx + qy * qy);  // (2.37)
  // clang-format on
  return R;
}

Quat QuatFromRotation(const Eigen::Matrix3d& R) {
  CheckFinite(R, "QuatFromRotation");
  // Four times the squares of q0, qx, qy, qz (2.38).
  const Eigen::Vector4d four_sq(1 + R(0, 0) + R(1, 1) + R(2, 2), 1 + R(0, 0) - R(1, 1) - R(2, 2),
                                1 - R(0, 0) + R(1, 1) - R(2, 2), 1 - R(0, 0) - R(1, 1) + R(2, 2));
  Eigen::Index k = 0;
  four_sq.maxCoeff(&k);
  const double qk = 0.5 * std::sqrt(std::max(four_sq[k], 0.0));  // the largest component, >= 1/2
  const double f = 0.25 / qk;
  // Products of pairs, times 4 (2.39).
  const double w_x = R(2, 1) - R(1, 2), w_y = R(0, 2) - R(2, 0), w_z = R(1, 0) - R(0, 1);
  const double x_y = R(0, 1) + R(1, 0), x_z = R(0, 2) + R(2, 0), y_z = R(1, 2) + R(2, 1);
  Quat q;
  switch (k) {
    case 0:
      q << qk, f * w_x, f * w_y, f * w_z;
      break;
    case 1:
      q << f * w_x, qk, f * x_y, f * x_z;
      break;
    case 2:
      q << f * w_y, f * x_y, qk, f * y_z;
      break;
    default:
      q << f * w_z, f * x_z, f * y_z, qk;
      break;
  }
  // Unit to rounding for a proper rotation; normalising also absorbs a matrix
  // slightly off SO(3).
  return CanonicalSign(NormalizedQuat(q, "QuatFromRotation"));
}

Eigen::Matrix3d RotationFromAngleAxis(const AngleAxis& aa) {
  if (!std::isfinite(aa.angle_rad) || !aa.axis.allFinite()) {
    throw std::invalid_argument("RotationFromAngleAxis: non-finite angle or axis");
  }
  const double n = aa.axis.norm();
  if (n < kMinQuaternionNorm) {
    if (aa.angle_rad == 0.0) return Eigen::Matrix3d::Identity();
    throw std::invalid_argument("RotationFromAngleAxis: zero axis with a non-zero angle");
  }
  const Eigen::Matrix3d S = Skew(aa.axis / n);                                                               // (2.22)
  return Eigen::Matrix3d::Identity() + std::sin(aa.angle_rad) * S + (1.0 - std::cos(aa.angle_rad)) * S * S;  // (2.21)
}

AngleAxis AngleAxisFromRotation(const Eigen::Matrix3d& R) {
  CheckFinite(R, "AngleAxisFromRotation");
  const Eigen::Vector3d sin_k = AntisymmetricPart(R);
  const double cos_theta = 0.5 * (R.trace() - 1.0);
  AngleAxis aa;
  aa.angle_rad = std::atan2(sin_k.norm(), cos_theta);  // (2.23)
  if (aa.angle_rad == 0.0) return aa;                  // any axis is valid
  if (cos_theta >= 0.0) {
    aa.axis = sin_k.normalized();  // (2.25)
    return aa;
  }
  // Symmetric part minus cos θ I equals (1 − cos θ) k kᵀ (2.26, generalised).
  const Eigen::Matrix3d kkT = (0.5 * (R + R.transpose()) - cos_theta * Eigen::Matrix3d::Identity()) / (1.0 - cos_theta);
  Eigen::Index i = 0;
  kkT.diagonal().maxCoeff(&i);  // (2.27): the largest
  const double ki = std::sqrt(std::max(kkT(i, i), 0.0));
  Eigen::Vector3d k = kkT.col(i) / ki;  // (2.28): k_i k_j / k_i
  if (k.dot(sin_k) < 0.0) k = -k;       // sign from R − Rᵀ; at θ = π it is 0 and k_i > 0 stays
  aa.axis = k.normalized();
  return aa;
}

Quat QuatFromAngleAxis(const AngleAxis& aa) {
  if (!std::isfinite(aa.angle_rad) || !aa.axis.allFinite()) {
    throw std::invalid_argument("QuatFromAngleAxis: non-finite angle or axis");
  }
  const double n = aa.axis.norm();
  if (n < kMinQuaternionNorm) {
    if (aa.angle_rad == 0.0) return IdentityQuat();
    throw std::invalid_argument("QuatFromAngleAxis: zero axis with a non-zero angle");
  }
  const double h = 0.5 * aa.angle_rad;
  Quat q;
  q << std::cos(h), std::sin(h) * aa.axis / n;  // (2.34)
  return q;
}

AngleAxis AngleAxisFromQuat(const Quat& q) {
  const Quat u = CanonicalSign(NormalizedQuat(q, "AngleAxisFromQuat"));
  const double s = u.tail<3>().norm();
  AngleAxis aa;
  aa.angle_rad = 2.0 * std::atan2(s, u[0]);
  if (s > 0.0) aa.axis = u.tail<3>() / s;
  return aa;
}

Quat QuatFromRotationVector(const Eigen::Vector3d& r) {
  const double theta = r.norm();
  if (theta == 0.0) return IdentityQuat();
  return QuatFromAngleAxis({theta, r / theta});
}

Eigen::Vector3d RotationVectorFromQuat(const Quat& q) {
  const AngleAxis aa = AngleAxisFromQuat(q);
  return aa.angle_rad * aa.axis;
}

Eigen::Matrix3d RotX(double gamma_rad) {
  const double c = std::cos(gamma_rad), s = std::sin(gamma_rad);
  Eigen::Matrix3d R;
  R << 1, 0, 0, 0, c, -s, 0, s, c;
  return R;
}

Eigen::Matrix3d RotY(double beta_rad) {
  const double c = std::cos(beta_rad), s = std::sin(beta_rad);
  Eigen::Matrix3d R;
  R << c, 0, s, 0, 1, 0, -s, 0, c;
  return R;
}

Eigen::Matrix3d RotZ(double alpha_rad) {
  const double c = std::cos(alpha_rad), s = std::sin(alpha_rad);
  Eigen::Matrix3d R;
  R << c, -s, 0, s, c, 0, 0, 0, 1;
  return R;
}

Eigen::Matrix3d RotationFromEulerZyx(const EulerZyx& e) {
  return RotZ(e.alpha_rad) * RotY(e.beta_rad) * RotX(e.gamma_rad);  // (2.19)
}

EulerZyx EulerZyxFromRotation(const Eigen::Matrix3d& R) {
  CheckFinite(R, "EulerZyxFromRotation");
  EulerZyx e;
  const double cos_beta = std::hypot(R(0, 0), R(1, 0));
  e.beta_rad = std::atan2(-R(2, 0), cos_beta);
  e.singular = cos_beta < kEulerSingularCos;
  if (!e.singular) {
    e.alpha_rad = std::atan2(R(1, 0), R(0, 0));
    e.gamma_rad = std::atan2(R(2, 1), R(2, 2));
    return e;
  }
  // Gimbal lock: with cos β = 0, R's upper-right block holds only γ − α (β > 0)
  // or γ + α (β < 0). Report it and put the whole angle on γ.
  e.alpha_rad = 0.0;
  e.gamma_rad = e.beta_rad > 0.0 ? std::atan2(R(0, 1), R(1, 1)) : std::atan2(-R(0, 1), R(1, 1));
  return e;
}

Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& M) {
  CheckFinite(M, "NearestRotation");
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

}  // namespace pose_math
