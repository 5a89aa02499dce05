// Pose covariance forms: the thesis's constrained 7×7 and ROS's 6×6.
//
// Thesis (5.6.4): Σ7 over Θ = (q0 qx qy qz tx ty tz), with the quaternion error
// constrained to the hyperplane tangent to the unit sphere at q̂ (5.68) (5.69).
//
// ROS (geometry_msgs/PoseWithCovariance): Σ6 over (x y z rx ry rz), where
// (rx ry rz) are small rotations about the fixed axes of the parent frame
// (the message's "fixed-axis representation"). We take that literally as a
// left perturbation: R_true = exp(S(δθ)) R̂, i.e. q_true = [1, δθ/2] ⊗ q̂.
// Then δq = G(q̂) δθ with G = ½ QR(q̂)[:, 1:3] (2.44), whose columns span the
// tangent hyperplane, so the two forms are exact images of each other:
//   Σ7 = J Σ6 Jᵀ,  J = [[0, G], [I, 0]] (rows q then t; columns t then θ),
//   Σ6 = J⁺ Σ7 J⁺ᵀ, J⁺ = [[0, I], [4Gᵀ, 0]]   (GᵀG = ¼ I).
// A Σ7 that is not on the hyperplane loses its component along q̂ in
// CovarianceRosFromThesis, exactly as ProjectToTangent would remove it.
#pragma once

#include <Eigen/Core>

#include "pose_math/pose.h"

namespace pose_math {

// Orthonormal basis of the null space of D = [q0 qx qy qz 0 0 0] (5.69) (5.70),
// computed with a Householder reflection as the thesis does. The result N is
// 7×6 with D N = 0 (5.71) and Nᵀ N = I.
Eigen::Matrix<double, 7, 6> QuaternionNullSpace(const Quat& q);

// Constrained least-squares covariance (5.74) of (5.72): for the stacked pose
// Jacobian A (m×7) and the measurement noise covariance already folded in as
// C = N ((AN)ᵀ(AN))⁻¹ (AN)ᵀ, returns Σ7 = C Σn Cᵀ (5.52) with (5.74). Here
// sigma_n is the m×m noise covariance of the residuals (B COV(n) Bᵀ of (5.52)).
// Throws std::invalid_argument if A N is rank deficient.
Matrix7d ConstrainedPoseCovariance(const Quat& q, const Eigen::MatrixXd& A, const Eigen::MatrixXd& sigma_n);

// P Σ Pᵀ with P = N Nᵀ, the orthogonal projector onto the tangent hyperplane.
Matrix7d ProjectToTangent(const Quat& q, const Matrix7d& cov7);

// 4×3 map from the fixed-axis rotation perturbation δθ to δq (see above).
Eigen::Matrix<double, 4, 3> RotationPerturbationToQuat(const Quat& q);

// Both directions of the conversion. q is the pose's orientation (normalised
// per quaternion.h). Results are symmetrised.
Matrix6d CovarianceRosFromThesis(const Quat& q, const Matrix7d& cov7);
Matrix7d CovarianceThesisFromRos(const Quat& q, const Matrix6d& cov6);

// Symmetrise (Σ + Σᵀ)/2. Returns false if any entry is non-finite.
bool SymmetrizeCovariance(Eigen::Ref<Eigen::MatrixXd> cov);

}  // namespace pose_math
