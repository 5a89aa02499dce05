// Rigid poses with covariance, in the thesis's 7-parameter form
// Θ = [q0 qx qy qz tx ty tz] (5.44).
//
// A Pose named T_a_b maps points from frame b to frame a: p_a = R(q) p_b + t
// (2.9). Chapter 4 estimates the model in the camera, T_camera_cones (C_M H,
// the OpenCV convention); the EKF keeps the camera in the model,
// T_cones_camera (M_C H). Invert() goes between the two.
//
// Covariances are 7×7 over (q, t) and live on the tangent hyperplane of the
// unit sphere at q (5.6.4, figure 5.3): q̂ · δq = 0. Every function here
// returns a covariance on that hyperplane.
#pragma once

#include <Eigen/Core>

#include "pose_math/quaternion.h"

namespace pose_math {

using Matrix7d = Eigen::Matrix<double, 7, 7>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector7d = Eigen::Matrix<double, 7, 1>;

struct Pose {
  Quat q = IdentityQuat();                      // thesis order, unit
  Eigen::Vector3d t = Eigen::Vector3d::Zero();  // metres
};

struct PoseWithCovariance {
  Pose pose;
  Matrix7d cov = Matrix7d::Zero();  // over (q0 qx qy qz tx ty tz)
};

// Θ as a 7-vector and back (the quaternion part is normalised on the way back).
Vector7d ToVector(const Pose& T);
Pose FromVector(const Vector7d& theta);

// p_a = R p_b + t.
Eigen::Vector3d Transform(const Pose& T_a_b, const Eigen::Vector3d& p_b);

// T_b_a from T_a_b: (q*, −R(q)ᵀ t).
Pose Invert(const Pose& T_a_b);
// T_a_c = T_a_b T_b_c: (q_ab ⊗ q_bc, R(q_ab) t_bc + t_ab).
Pose Compose(const Pose& T_a_b, const Pose& T_b_c);

// Jacobians of Invert and Compose with respect to Θ, for covariance
// propagation Σ' = J Σ Jᵀ (first order, as in (5.52)).
Matrix7d InvertJacobian(const Pose& T_a_b);
void ComposeJacobians(const Pose& T_a_b, const Pose& T_b_c, Matrix7d* J_wrt_ab, Matrix7d* J_wrt_bc);

// The same operations carrying covariance. Compose treats the two inputs as
// independent.
PoseWithCovariance Invert(const PoseWithCovariance& T_a_b);
PoseWithCovariance Compose(const PoseWithCovariance& T_a_b, const PoseWithCovariance& T_b_c);

// T_a_b at time t from two earlier poses of b in a (t_prev_s < t_new_s <= t_s): b keeps the body rate and the
// velocity it had between them (constant-rate extrapolation). With t_new_s <= t_prev_s, T_a_b_new unchanged.
Pose ExtrapolateConstantRate(const Pose& T_a_b_prev, double t_prev_s, const Pose& T_a_b_new, double t_new_s,
                             double t_s);

// Distance between two poses: the rotation angle of R_aᵀ R_b (rad) and the
// translation difference (m). Used by tests and accuracy reports.
double RotationErrorRad(const Pose& a, const Pose& b);
double TranslationError(const Pose& a, const Pose& b);

}  // namespace pose_math
