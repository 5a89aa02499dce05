// Quaternions in the thesis's convention (Steinbis 2008, section 2.2.3).
//
// A quaternion is an Eigen::Vector4d in the thesis's order [q0 qx qy qz]
// (scalar first, 2.30). Eigen::Quaterniond stores its coefficients as
// (x, y, z, w); the only crossing between the two is ThesisFromEigen() /
// EigenFromThesis(), so nobody reorders coefficients by hand.
//
// Input policy, shared by every function in pose_math that takes a quaternion:
//   - a non-finite coefficient, or a norm below kMinQuaternionNorm, throws
//     std::invalid_argument naming the function;
//   - a finite quaternion that is not unit length is normalised (2.31) first,
//     except where a function says it takes a general (non-unit) quaternion.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace pose_math {

using Quat = Eigen::Vector4d;  // thesis order [q0 qx qy qz]

constexpr double kMinQuaternionNorm = 1e-12;

// Conversions between the thesis's order and Eigen's. Not normalised.
Quat ThesisFromEigen(const Eigen::Quaterniond& q);
Eigen::Quaterniond EigenFromThesis(const Quat& q);

// Identity rotation quaternion (2.35).
inline Quat IdentityQuat() { return Quat(1.0, 0.0, 0.0, 0.0); }

// Throws std::invalid_argument (message starts with `what`) if q is not finite
// or its norm is below kMinQuaternionNorm; otherwise returns q / |q| (2.31).
Quat NormalizedQuat(const Quat& q, const char* what = "quaternion");

// Conjugate q* (2.32). Equal to the inverse q^-1 (2.33) for unit q.
Quat Conjugate(const Quat& q);

// Sign choice: the same rotation with q0 >= 0 (R(q) = R(-q), section 2.2.3).
Quat CanonicalSign(const Quat& q);

// Quaternion product p ⊗ q (2.40). Works on general (non-unit) quaternions.
Quat Multiply(const Quat& p, const Quat& q);

// Left and right product matrices (2.44): p ⊗ q = QL(p) q = QR(q) p.
Eigen::Matrix4d LeftMatrix(const Quat& p);
Eigen::Matrix4d RightMatrix(const Quat& q);

// The skew-symmetric matrix S(w) with S(w) v = w × v (2.50).
Eigen::Matrix3d Skew(const Eigen::Vector3d& w);

// QR(Ω) of the pure quaternion Ω = [0 ω] (2.69), so that q̇ = ½ QR(Ω) q (2.68)
// for an angular velocity ω expressed in the body frame.
Eigen::Matrix4d OmegaMatrix(const Eigen::Vector3d& omega_body_rad_s);

// One step of q̇ = ½ q ⊗ [0 ω] with ω constant over dt, ω in the body frame.
// First order (2.70): q + dt/2 QR(Ω) q, then normalised (5.41).
Quat IntegrateFirstOrder(const Quat& q, const Eigen::Vector3d& omega_body_rad_s, double dt_s);
// Exact for constant ω (2.71): [cos(|ω|dt/2) I + sin(|ω|dt/2)/|ω| QR(Ω)] q.
Quat IntegrateExact(const Quat& q, const Eigen::Vector3d& omega_body_rad_s, double dt_s);

// Rotates v by q: the vector part of q ⊗ [0 v] ⊗ q* (2.42).
Eigen::Vector3d Rotate(const Quat& q, const Eigen::Vector3d& v);

// d(R(q) v)/dq for a general (non-unit) q with R(q) from (2.36): a 3×4 matrix.
// Used for covariance propagation and for the pose Jacobians of (5.59) and (5.66).
Eigen::Matrix<double, 3, 4> RotateJacobianWrtQuat(const Quat& q, const Eigen::Vector3d& v);

}  // namespace pose_math
