// First-order pose covariance from image noise (section 5.6): image-space
// (5.56) (5.57) and object-space (5.63) (5.64) (5.65) error functions, with
// the quaternion pose Θ = [q0 qx qy qz tx ty tz] (5.44) under the unit-norm
// constraint (section 5.6.4, via pose_math::ConstrainedPoseCovariance) or with
// ZYX Euler angles Θ = [α β γ tx ty tz] (unconstrained: (5.48) and (5.52)).
#pragma once
#include <Eigen/Core>

#include "cone_tracker/pose/algorithms.h"
#include "pose_math/pose.h"
#include "pose_math/rotation.h"

namespace cone_tracker {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Per-point residuals at zero noise and their Jacobians (A_i w.r.t. the pose,
// B_i w.r.t. the normalised image noise for object space).
Eigen::Vector2d ImageResidual(const pose_math::Pose& T, const Eigen::Vector3d& model, const Eigen::Vector2d& normalized,
                              double fx_px, double fy_px);
Eigen::Vector3d ObjectResidual(const pose_math::Pose& T, const Eigen::Vector3d& model,
                               const Eigen::Vector2d& normalized);
Eigen::Matrix<double, 2, 7> ImageJacobianQuat(const pose_math::Pose& T, const Eigen::Vector3d& model, double fx_px,
                                              double fy_px);  // (5.59)
void ObjectJacobiansQuat(const pose_math::Pose& T, const Eigen::Vector3d& model, const Eigen::Vector2d& normalized,
                         Eigen::Matrix<double, 3, 7>* A, Eigen::Matrix<double, 3, 2>* B);  // (5.66)
// Euler: the pose is (e, t) with R = RotationFromEulerZyx(e).
Eigen::Matrix<double, 2, 6> ImageJacobianEuler(const pose_math::EulerZyx& e, const Eigen::Vector3d& t,
                                               const Eigen::Vector3d& model, double fx_px, double fy_px);
void ObjectJacobiansEuler(const pose_math::EulerZyx& e, const Eigen::Vector3d& t, const Eigen::Vector3d& model,
                          const Eigen::Vector2d& normalized, Eigen::Matrix<double, 3, 6>* A,
                          Eigen::Matrix<double, 3, 2>* B);

// Σ over Θ for isotropic pixel noise σ. Throws std::invalid_argument if the
// pose Jacobian is rank deficient.
pose_math::Matrix7d PoseCovarianceQuat(const Correspondences& c, const pose_math::Pose& T, ErrorSpace space,
                                       double sigma_px);
Matrix6d PoseCovarianceEuler(const Correspondences& c, const pose_math::Pose& T, ErrorSpace space, double sigma_px);

}  // namespace cone_tracker
