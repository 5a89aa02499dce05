// The chapter 4 algorithms on undistorted, normalised observations. SolvePnp()
// (pnp.h) validates input and dispatches here; tests and the experiments call
// these directly to run linear stages and refinements separately.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "cone_tracker/pose/pnp.h"
#include "pose_math/pose.h"

namespace cone_tracker {

// Model points and their normalised image points w = [(u−u0)/fu, (v−v0)/fv, 1]
// (4.4); fx/fy turn normalised errors back into pixels for image-space methods.
struct Correspondences {
  Eigen::Matrix3Xd model;       // {M}
  Eigen::Matrix2Xd normalized;  // undistorted, unit focal length
  double fx_px = 1.0;
  double fy_px = 1.0;
  int size() const { return static_cast<int>(model.cols()); }
};

struct Estimate {
  bool ok = false;
  std::string error;
  pose_math::Pose T_camera_model;
  int iterations = 0;
  bool converged = false;
  double rotation_nonorthogonality = 0.0;  // DLT only
};
Estimate Failure(const std::string& message);

// --- geometry helpers (geometry.cpp) ---
pose_math::Pose PoseFromRt(const Eigen::Matrix3d& R, const Eigen::Vector3d& t);
Eigen::Matrix3d RotationOf(const pose_math::Pose& T);
// Orthogonal projector F = w wᵀ / (wᵀ w) onto the line of sight of w (4.3).
Eigen::Matrix3d LineOfSightProjector(const Eigen::Vector2d& normalized);
// Mean squared reprojection error in pixels (4.1) and object-space error (4.2).
double ImageSpaceCost(const Correspondences& c, const pose_math::Pose& T);
double ObjectSpaceCost(const Correspondences& c, const pose_math::Pose& T);
// Smallest depth of any model point in the camera (≤ 0: something behind it).
double MinDepth(const Eigen::Matrix3Xd& model, const pose_math::Pose& T);
// Singular values of the centred model points, largest first.
Eigen::Vector3d ModelSpread(const Eigen::Matrix3Xd& model);
// d R(α,β,γ)/d(α,β,γ) for R = Rz(α) Ry(β) Rx(γ) (2.19).
void EulerRotationDerivatives(double alpha, double beta, double gamma, Eigen::Matrix3d dR[3]);

// --- absolute orientation, Horn (absolute_orientation.cpp) ---
// T with camera ≈ R model + t (thesis 4.2.3). SVD with determinant fix (4.2.3.1)
// or the quaternion eigenvector (4.2.3.2).
pose_math::Pose AbsoluteOrientationSvd(const Eigen::Matrix3Xd& model, const Eigen::Matrix3Xd& camera);
pose_math::Pose AbsoluteOrientationQuat(const Eigen::Matrix3Xd& model, const Eigen::Matrix3Xd& camera);

// --- classic algorithms ---
Estimate P3pFischlerBolles(const Correspondences& c);  // p3p.cpp, n ≥ 4
Estimate Dlt(const Correspondences& c);                // dlt.cpp, n ≥ 6, non-planar
// Lu–Hager (oia.cpp). Without an initial pose it starts from the weak-perspective
// guess of the original paper (all depths equal).
Estimate OrthogonalIteration(const Correspondences& c, const pose_math::Pose* initial, int max_iterations = 200,
                             double relative_tolerance = 1e-12);

// --- null-space algorithms (linear_system.cpp, mdlt.cpp, simplex.cpp) ---
Estimate MdltLinear(const Correspondences& c, ErrorSpace space);
Estimate MdltGaussNewton(const Correspondences& c, ErrorSpace space, const pose_math::Pose& initial,
                         int max_iterations = 30);
Estimate SimplexLinear(const Correspondences& c, ErrorSpace space);
Estimate SimplexGaussNewton(const Correspondences& c, ErrorSpace space, const pose_math::Pose& initial,
                            int max_iterations = 30);
// EPnP (epnp.cpp): linear (best of 1–3 eigenvectors) and with Gauss–Newton on
// four betas.
Estimate EpnpLinear(const Correspondences& c);
Estimate EpnpGaussNewton(const Correspondences& c);
// 3-simplex SDP (simplex_sdp.cpp).
Estimate SimplexSdp(const Correspondences& c, ErrorSpace space, int eigenvectors, PnpOptions::SdpConstraint constraint);

// --- refinement (ceres_refine.cpp) ---
Estimate CeresRefine(const Correspondences& c, const pose_math::Pose& initial, bool robust_loss,
                     double huber_threshold_px, int max_iterations);
// The same least squares with ceres::TinySolver (dense Levenberg–Marquardt,
// no Problem set-up) in a rotation-vector chart around the start: the fast
// refinement of "best". No robust loss.
Estimate TinyCeresRefine(const Correspondences& c, const pose_math::Pose& initial, int max_iterations = 50);
// Its residuals (pixels) and Jacobian at x = (δθ, t) around `origin`, for tests.
void ChartResidualsAndJacobian(const Correspondences& c, const pose_math::Pose& origin,
                               const Eigen::Matrix<double, 6, 1>& x, Eigen::VectorXd* residuals,
                               Eigen::MatrixXd* jacobian);

}  // namespace cone_tracker
