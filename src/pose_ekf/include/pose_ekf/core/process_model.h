// The EKF's models as free functions (thesis sections 5.4 and 5.5), so tests can check the
// analytic Jacobians against numeric ones.
//
// State (5.18): x = [q ω p v a (b)] with q = M_C q (camera in cones, thesis
// order), ω = C ω_cam (body rate in the camera frame), p, v, a of the camera in
// the cones frame, and optionally b, the gyro bias in the camera frame.
#pragma once

#include <Eigen/Core>

#include "pose_ekf/core/config.h"

namespace pose_ekf {

constexpr int kQ = 0, kW = 4, kP = 7, kV = 10, kA = 13, kB = 16;
constexpr int kBaseStates = 16, kMaxStates = 19;

// Fixed maximum size: no heap allocation, 16 or 19 states at run time.
using StateVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxStates, 1>;
using StateMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxStates, kMaxStates>;

inline int StateSize(const EkfConfig& c) { return c.estimate_gyro_bias ? kMaxStates : kBaseStates; }

// f(x, dt) (5.20), i.e. (5.19) with the quaternion update (5.21), without
// noise; the quaternion is NOT renormalised here (the core does that), so that
// TransitionJacobian is its exact derivative.
StateVector PropagateState(const StateVector& x, double dt_s, QuatIntegration integration);

// F = ∂f/∂x (5.22); for kExact the derivative of (2.71).
StateMatrix TransitionJacobian(const StateVector& x, double dt_s, QuatIntegration integration);

// Linear time-varying process noise Q = dt diag(σ²) (5.23).
StateMatrix ProcessNoise(const EkfConfig& c, int n, double dt_s);

// Accelerometer model: R(q)ᵀ g_M (5.36) or R(q)ᵀ (a + g_M) (5.39), with g_M =
// [0 0 g] (specific force at rest points up, z up in cones), R from the general
// form (2.36) so that AccelJacobian is exact for non-unit q as well.
Eigen::Vector3d AccelModel(const StateVector& x, double gravity_m_s2, AccelMode mode);
// ∂h/∂x: 3×n (5.37) or (5.40).
Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxStates> AccelJacobian(const StateVector& x, double gravity_m_s2,
                                                                         AccelMode mode);

}  // namespace pose_ekf
