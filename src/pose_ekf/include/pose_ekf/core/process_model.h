// The EKF's models as free functions (thesis sections 5.4 and 5.5), so tests can check the
// analytic Jacobians against numeric ones.
//
// State (5.18): x = [q ω p v a (b)] with q = M_C q (camera in cones, thesis
// order), ω = C ω_cam (body rate in the camera frame), p, v, a of the camera in
// the cones frame, and optionally b, the gyro bias in the camera frame, and
// b_a, the accelerometer bias in the camera frame (after b when both are on).
#pragma once

#include <Eigen/Core>

#include "pose_ekf/core/config.h"

namespace pose_ekf {

constexpr int kQ = 0, kW = 4, kP = 7, kV = 10, kA = 13, kB = 16;
constexpr int kBaseStates = 16, kMaxStates = 22;

// Fixed maximum size: no heap allocation, 16, 19 or 22 states at run time.
using StateVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxStates, 1>;
using StateMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxStates, kMaxStates>;

inline int StateSize(const EkfConfig& c) {
  return kBaseStates + (c.estimate_gyro_bias ? 3 : 0) + (c.estimate_accel_bias ? 3 : 0);
}
// Index of the accelerometer bias b_a in the state, -1 when it is not estimated.
inline int AccelBiasIndex(const EkfConfig& c) {
  return c.estimate_accel_bias ? (c.estimate_gyro_bias ? kB + 3 : kB) : -1;
}

// f(x, dt) (5.20), i.e. (5.19) with the quaternion update (5.21), without
// noise; the quaternion is NOT renormalised here (the core does that), so that
// TransitionJacobian is its exact derivative.
// Beyond the thesis, velocity_time_constant_s > 0 damps v and accel_time_constant_s > 0
// damps a by exp(-dt/τ) per step (0: the thesis's undamped (5.19)), so that a long
// camera outage does not integrate a and v into an unbounded position drift.
StateVector PropagateState(const StateVector& x, double dt_s, QuatIntegration integration,
                           double velocity_time_constant_s = 0.0, double accel_time_constant_s = 0.0);

// F = ∂f/∂x (5.22); for kExact the derivative of (2.71).
StateMatrix TransitionJacobian(const StateVector& x, double dt_s, QuatIntegration integration,
                               double velocity_time_constant_s = 0.0, double accel_time_constant_s = 0.0);

// F P Fᵀ for an F of TransitionJacobian's shape: identity but for the rows of q
// (which read q and ω) and of p, v, a (which read p, v, a). It touches only those
// bands, ~10 times fewer flops than the dense product at 22 states; equal to it
// (test_process_model.cpp).
StateMatrix PropagateCovariance(const StateMatrix& F, const StateMatrix& P);

// Linear time-varying process noise Q = dt diag(σ²) (5.23); the bias blocks follow
// c.estimate_gyro_bias and c.estimate_accel_bias (n must be StateSize(c)).
StateMatrix ProcessNoise(const EkfConfig& c, int n, double dt_s);

// Accelerometer model: R(q)ᵀ g_M (5.36) or R(q)ᵀ (a + g_M) (5.39), with g_M =
// [0 0 g] (specific force at rest points up, z up in cones), R from the general
// form (2.36) so that AccelJacobian is exact for non-unit q as well.
Eigen::Vector3d AccelModel(const StateVector& x, double gravity_m_s2, AccelMode mode);
// ∂h/∂x: 3×n (5.37) or (5.40).
Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxStates> AccelJacobian(const StateVector& x, double gravity_m_s2,
                                                                         AccelMode mode);

// The same at an IMU mounted at p_imu_in_camera_m (r, the lever arm, camera
// frame) and read in camera axes, with the accelerometer bias b_a at
// accel_bias_index (-1: none): h = (5.36)/(5.39) + ω×(ω×r) + b_a. The α×r term
// is left to the measurement noise (AccelLeverArmNoise): α is not in the state.
Eigen::Vector3d AccelModel(const StateVector& x, double gravity_m_s2, AccelMode mode,
                           const Eigen::Vector3d& p_imu_in_camera_m, int accel_bias_index);
Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxStates> AccelJacobian(const StateVector& x, double gravity_m_s2,
                                                                         AccelMode mode,
                                                                         const Eigen::Vector3d& p_imu_in_camera_m,
                                                                         int accel_bias_index);
// Covariance of α×r for an angular acceleration α of sigma_rad_s2 per axis: σ² [r]× [r]×ᵀ.
Eigen::Matrix3d AccelLeverArmNoise(const Eigen::Vector3d& p_imu_in_camera_m, double sigma_angular_accel_rad_s2);

}  // namespace pose_ekf
