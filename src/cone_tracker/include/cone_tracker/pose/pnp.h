// The single-frame pose API (Steinbis 2008, chapter 4, with the uncertainty of 5.6).
//
// SolvePnp() takes the camera intrinsics and distortion, model points in {M}
// and their pixel observations, and returns the model in the camera,
// T_camera_model: p_c = R p_m + t (OpenCV's convention), with residuals,
// iteration count, a converged flag and the covariance in both the thesis's
// constrained 7×7 form and ROS's 6×6 form (pose_math). ROS-free.
//
// Degenerate input (too few points for the method, collinear or, where the
// method needs depth spread, planar model points, non-finite values, a
// solution or initial pose with points behind the camera) returns ok = false
// with a message; the pose is then left at identity and must not be used.
#pragma once
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "pose_math/pose.h"
#include "rig_model/camera_model.h"

namespace cone_tracker {

// The rig's camera (rig_model): pinhole intrinsics plus OpenCV's distortion vector
// (k1 k2 p1 p2 [k3 ...]), which the tracker hands to OpenCV as it is.
using CameraModel = rig_model::CameraModel;

enum class PnpMethod {
  kP3p,         // Fischler–Bolles (thesis 4.2.1), extra points pick the root
  kDlt,         // Abdel-Aziz & Karara (thesis 4.2.2)
  kOia,         // Lu–Hager orthogonal iteration (thesis 4.2.4)
  kMdltIs,      // MDLT linear + Gauss–Newton, image space (thesis 4.3.1)
  kMdltOs,      // the same in object space
  kSimplexIs,   // 3-simplex linear + Gauss–Newton, image space (thesis 4.3.2)
  kSimplexOs,   // the same in object space
  kEpnp,        // EPnP, linear (Moreno-Noguer et al. 2007)
  kEpnpGn,      // EPnP with Gauss–Newton on the betas
  kSimplexSdp,  // 3-simplex SDP with CSDP (thesis 4.3.3)
  kCeres,       // Ceres image-space refinement on the quaternion manifold
  kBest,        // linear initialisation + refinement: what the tracker uses
};

// Method names as used by pnp_solve ("p3p", "dlt", ..., "best").
const std::vector<std::string>& PnpMethodNames();
std::optional<PnpMethod> PnpMethodFromName(const std::string& name);
std::string PnpMethodName(PnpMethod method);

enum class ErrorSpace { kImage, kObject };

struct PnpOptions {
  PnpMethod method = PnpMethod::kBest;
  // Image noise used for the covariance: cov(n) (5.54) in image space, (5.62) in object space.
  double sigma_px = 1.0;
  bool compute_covariance = true;
  // Ceres / best: optional Huber loss on the reprojection error.
  bool robust_loss = false;
  double huber_threshold_px = 2.0;
  int max_iterations = 100;
  // best: restart from other starts when the refined RMS reprojection error
  // per image coordinate exceeds this multiple of sigma_px. At the global
  // minimum it is about σ sqrt(1 − 3/n), so 1.1 restarts only a few percent of frames whose noise
  // matches sigma_px (about 4% with 9 points) and catches most local minima.
  double best_restart_rms_factor = 1.1;
  // Simplex SDP: number of eigenvectors (2, 3 or 4) and constraint kind.
  int sdp_eigenvectors = 4;
  enum class SdpConstraint { kDistance, kDotProduct, kOrthogonalTriad } sdp_constraint = SdpConstraint::kDistance;
};

struct PnpResult {
  bool ok = false;
  std::string error;                          // set when !ok
  pose_math::Pose T_camera_model;             // p_c = R p_m + t
  std::vector<Eigen::Vector2d> residuals_px;  // projected − observed (undistorted), per point
  double reproj_rms_px = 0.0;
  int iterations = 0;
  bool converged = false;
  // DLT only: ‖RᵀR − I‖_F of the raw DLT rotation before orthogonalisation.
  double rotation_nonorthogonality = 0.0;
  // Covariance of T_camera_model: thesis 7×7 over (q0 qx qy qz tx ty tz) on the
  // tangent hyperplane (thesis 5.6.4), and its ROS image (x y z rx ry rz).
  ErrorSpace covariance_space = ErrorSpace::kImage;
  pose_math::Matrix7d cov7 = pose_math::Matrix7d::Zero();
  pose_math::Matrix6d cov6_ros = pose_math::Matrix6d::Zero();
};

PnpResult SolvePnp(const CameraModel& camera, const std::vector<Eigen::Vector3d>& model_points,
                   const std::vector<Eigen::Vector2d>& image_points_px, const PnpOptions& options,
                   const std::optional<pose_math::Pose>& initial_T_camera_model = std::nullopt);

}  // namespace cone_tracker
