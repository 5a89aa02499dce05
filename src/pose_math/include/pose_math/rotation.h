// Rotation parameterisations (Steinbis 2008, section 2.2): rotation matrix,
// quaternion, angle-axis and ZYX Euler angles. Quaternions are in the thesis's
// order [q0 qx qy qz]; see quaternion.h for the input policy.
//
// Rotation matrices are taken to be proper rotations. Functions that extract a
// parameterisation from a matrix throw std::invalid_argument on a non-finite
// entry; for a matrix that is only close to SO(3) (a DLT result, say) call
// NearestRotation() first.
#pragma once

#include <Eigen/Core>

#include "pose_math/quaternion.h"

namespace pose_math {

// R(q) for a unit quaternion (2.37). Non-unit input is normalised first.
Eigen::Matrix3d RotationFromQuat(const Quat& q);

// Quaternion of R by the largest-diagonal extraction (2.38) (2.39), with q0 >= 0.
Quat QuatFromRotation(const Eigen::Matrix3d& R);

// Euler angle-axis. angle_rad is in [0, π]; axis is a unit vector.
struct AngleAxis {
  double angle_rad = 0.0;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
};

// R = I + sin θ S + (1 − cos θ) S² (2.21). A non-unit axis is normalised; a
// zero axis is allowed only with θ = 0. Throws on non-finite input.
Eigen::Matrix3d RotationFromAngleAxis(const AngleAxis& aa);

// Angle-axis of R (section 2.2.2). θ is computed as atan2(|R − Rᵀ|/2, (tr R − 1)/2),
// the same angle as (2.23) without acos's loss of precision near 0 and π. For
// θ ≤ π/2 the axis comes from R − Rᵀ (2.24) (2.25); above π/2 it comes from the
// largest diagonal entry of the symmetric part ((2.26) (2.27) (2.28), generalised from
// θ = π to any θ), with its sign taken from R − Rᵀ. At θ = 0 the axis is
// undefined and UnitX is returned; at θ = π both ±k are valid and the one with
// a non-negative largest component is returned.
AngleAxis AngleAxisFromRotation(const Eigen::Matrix3d& R);

// q0 = cos(θ/2), q⃗ = sin(θ/2) k (2.34).
Quat QuatFromAngleAxis(const AngleAxis& aa);
// Inverse of (2.34), θ in [0, π] (the sign of q is chosen so that q0 >= 0).
AngleAxis AngleAxisFromQuat(const Quat& q);

// Rotation vector r = θ k and back (exponential / logarithm maps). Used for the
// rotation part of ROS's 6×6 pose covariance.
Quat QuatFromRotationVector(const Eigen::Vector3d& r);
Eigen::Vector3d RotationVectorFromQuat(const Quat& q);

// Elementary rotations (2.17).
Eigen::Matrix3d RotX(double gamma_rad);
Eigen::Matrix3d RotY(double beta_rad);
Eigen::Matrix3d RotZ(double alpha_rad);

// ZYX Euler angles: R = Rz(α) Ry(β) Rx(γ) (2.19).
struct EulerZyx {
  double alpha_rad = 0.0;  // about z, first
  double beta_rad = 0.0;   // about y, in [-π/2, π/2]
  double gamma_rad = 0.0;  // about x, last
  // True when |cos β| < kEulerSingularCos, i.e. |β| within ~1e-7 rad of π/2
  // ("gimbal lock", section 2.2.1). Then only α − γ (β > 0) or α + γ (β < 0)
  // is determined; α is set to 0 and γ carries the whole remaining rotation.
  bool singular = false;
};
constexpr double kEulerSingularCos = 1e-7;

Eigen::Matrix3d RotationFromEulerZyx(const EulerZyx& e);
EulerZyx EulerZyxFromRotation(const Eigen::Matrix3d& R);

// The rotation closest to M in the Frobenius norm: U diag(1, 1, det(UVᵀ)) Vᵀ
// from the SVD M = U Σ Vᵀ (4.39) (4.40), with the determinant fix of the
// thesis's reference [40]. Throws on non-finite M.
Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& M);

}  // namespace pose_math
