#include "imu_driver/core/camera_imu_rotation.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "pose_math/rotation.h"

namespace imu_driver {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// Smallest singular value of the stacked directions, relative: ~0 when all
// gravity directions are parallel and the rotation about them is unobservable.
double DirectionSpread(const std::vector<GravityPair>& pairs) {
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  for (const auto& p : pairs) S += p.up_in_imu * p.up_in_imu.transpose();
  const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(S).eigenvalues();
  return ev(2) > 0 ? ev(1) / ev(2) : 0.0;
}

bool Usable(const std::vector<GravityPair>& pairs, std::string* why) {
  if (pairs.size() < 2) {
    *why = "need at least 2 static poses, got " + std::to_string(pairs.size());
    return false;
  }
  for (const auto& p : pairs) {
    if (!p.up_in_imu.allFinite() || !p.up_in_camera.allFinite() || p.up_in_imu.norm() < 1e-9 ||
        p.up_in_camera.norm() < 1e-9) {
      *why = "a gravity vector is zero or not finite";
      return false;
    }
  }
  if (DirectionSpread(pairs) < 1e-4) {
    *why = "all gravity directions are parallel: tilt the rig between poses";
    return false;
  }
  return true;
}

Eigen::Matrix3d Euler(const Eigen::Vector3d& abg) {
  return pose_math::RotationFromEulerZyx(pose_math::EulerZyx{abg(0), abg(1), abg(2), false});
}

}  // namespace

GravityPair MakeGravityPair(const Eigen::Vector3d& accel_mean_imu_m_s2, const Eigen::Matrix3d& R_camera_grid,
                            const Eigen::Vector3d& up_in_grid) {
  return {accel_mean_imu_m_s2.normalized(), (R_camera_grid * up_in_grid).normalized()};  // (3.28)
}

double RmsResidualDeg(const std::vector<GravityPair>& pairs, const Eigen::Matrix3d& R) {
  if (pairs.empty()) return 0.0;
  double ss = 0.0;
  for (const auto& p : pairs) {
    const Eigen::Vector3d a = R * p.up_in_imu.normalized();
    const Eigen::Vector3d b = p.up_in_camera.normalized();
    const double angle = std::atan2(a.cross(b).norm(), a.dot(b));
    ss += angle * angle;
  }
  return std::sqrt(ss / pairs.size()) * kRadToDeg;
}

RotationFit FitRotationSvd(const std::vector<GravityPair>& pairs) {
  RotationFit fit;
  if (!Usable(pairs, &fit.message)) return fit;
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (const auto& p : pairs) M += p.up_in_camera.normalized() * p.up_in_imu.normalized().transpose();  // (3.32)
  fit.R_camera_imu = pose_math::NearestRotation(M);  // U diag(1,1,det(UVᵀ)) Vᵀ (3.33) (3.34)
  fit.rms_residual_deg = RmsResidualDeg(pairs, fit.R_camera_imu);
  fit.ok = true;
  return fit;
}

Eigen::Matrix3d FitLinearLeastSquares(const std::vector<GravityPair>& pairs) {
  Eigen::Matrix3d CI = Eigen::Matrix3d::Zero(), II = Eigen::Matrix3d::Zero();
  for (const auto& p : pairs) {
    CI += p.up_in_camera.normalized() * p.up_in_imu.normalized().transpose();
    II += p.up_in_imu.normalized() * p.up_in_imu.normalized().transpose();
  }
  return CI * II.completeOrthogonalDecomposition().pseudoInverse();  // (3.30)
}

RotationFit FitRotationEuler(const std::vector<GravityPair>& pairs, const Eigen::Matrix3d& initial_guess) {
  RotationFit fit;
  if (!Usable(pairs, &fit.message)) return fit;
  const pose_math::EulerZyx e0 = pose_math::EulerZyxFromRotation(pose_math::NearestRotation(initial_guess));
  Eigen::Vector3d x(e0.alpha_rad, e0.beta_rad, e0.gamma_rad);
  const size_t n = pairs.size();
  auto residual = [&](const Eigen::Vector3d& abg) {
    Eigen::VectorXd r(3 * n);
    const Eigen::Matrix3d R = Euler(abg);
    for (size_t i = 0; i < n; ++i) {
      r.segment<3>(3 * i) = R * pairs[i].up_in_imu.normalized() - pairs[i].up_in_camera.normalized();  // (3.31)
    }
    return r;
  };
  double lambda = 1e-3;
  Eigen::VectorXd r = residual(x);
  double cost = r.squaredNorm();
  for (fit.iterations = 1; fit.iterations <= 100; ++fit.iterations) {
    Eigen::MatrixXd J(3 * n, 3);
    for (int k = 0; k < 3; ++k) {  // central differences: the cost is smooth and cheap
      Eigen::Vector3d h = Eigen::Vector3d::Zero();
      h(k) = 1e-6;
      J.col(k) = (residual(x + h) - residual(x - h)) / 2e-6;
    }
    const Eigen::Matrix3d A = J.transpose() * J;
    const Eigen::Vector3d g = J.transpose() * r;
    const Eigen::Vector3d step = (A + lambda * Eigen::Matrix3d(A.diagonal().asDiagonal())).ldlt().solve(-g);
    const Eigen::VectorXd r_new = residual(x + step);
    if (r_new.squaredNorm() < cost) {
      x += step;
      r = r_new;
      const double improvement = cost - r.squaredNorm();
      cost = r.squaredNorm();
      lambda = std::max(lambda / 10.0, 1e-12);
      if (step.norm() < 1e-12 || improvement < 1e-16) break;
    } else {
      lambda *= 10.0;
      if (lambda > 1e12) break;
    }
  }
  fit.R_camera_imu = Euler(x);
  fit.rms_residual_deg = RmsResidualDeg(pairs, fit.R_camera_imu);
  fit.ok = true;
  return fit;
}

}  // namespace imu_driver
