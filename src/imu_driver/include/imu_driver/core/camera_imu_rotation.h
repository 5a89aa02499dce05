// Camera–IMU relative rotation from gravity (thesis 3.2.2).
//
// At each static calibration pose i the averaged accelerometer gives gravity
// in the IMU frame, a_I_i, and the camera calibration's extrinsics R_camera_grid_i
// carry the known gravity direction of the grid into the camera, a_C_i (3.28).
// R_camera_imu maps the first set onto the second (3.29). Both vectors are the
// accelerometer's rest reading ("up"), normalised, so the grid's up direction
// is what the caller supplies.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace imu_driver {

struct GravityPair {
  Eigen::Vector3d up_in_imu;     // averaged accelerometer at rest, {I}
  Eigen::Vector3d up_in_camera;  // R_camera_grid * up_in_grid, {C} (3.28)
};

// a_C = R_camera_grid * up_in_grid for each pose (3.28).
GravityPair MakeGravityPair(const Eigen::Vector3d& accel_mean_imu_m_s2, const Eigen::Matrix3d& R_camera_grid,
                            const Eigen::Vector3d& up_in_grid);

struct RotationFit {
  bool ok = false;
  std::string message;
  Eigen::Matrix3d R_camera_imu = Eigen::Matrix3d::Identity();
  double rms_residual_deg = 0.0;  // angle between R a_I and a_C, RMS over the poses
  int iterations = 0;             // for the iterative method
};

// The SVD of the moment matrix M = Σ a_C a_Iᵀ (3.32) (3.33) (3.34), with the
// determinant fix so the result is a proper rotation. Needs two or more
// non-parallel gravity directions.
RotationFit FitRotationSvd(const std::vector<GravityPair>& pairs);

// Unconstrained linear least squares (3.30): C = A_C A_Iᵀ (A_I A_Iᵀ)⁻¹. Not
// orthogonal in general; returned as is (needs three independent directions).
Eigen::Matrix3d FitLinearLeastSquares(const std::vector<GravityPair>& pairs);

// Nonlinear minimisation of E = Σ |R(α,β,γ) a_I − a_C|² over ZYX Euler angles
// (3.31) by Levenberg–Marquardt from an initial guess.
RotationFit FitRotationEuler(const std::vector<GravityPair>& pairs,
                             const Eigen::Matrix3d& initial_guess = Eigen::Matrix3d::Identity());

double RmsResidualDeg(const std::vector<GravityPair>& pairs, const Eigen::Matrix3d& R_camera_imu);

}  // namespace imu_driver
