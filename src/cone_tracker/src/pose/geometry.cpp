// Small geometry shared by the chapter 4 algorithms.
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "cone_tracker/pose/algorithms.h"
#include "pose_math/rotation.h"

namespace cone_tracker {

Estimate Failure(const std::string& message) {
  Estimate e;
  e.ok = false;
  e.error = message;
  return e;
}

pose_math::Pose PoseFromRt(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  pose_math::Pose T;
  T.q = pose_math::QuatFromRotation(R);
  T.t = t;
  return T;
}

Eigen::Matrix3d RotationOf(const pose_math::Pose& T) { return pose_math::RotationFromQuat(T.q); }

Eigen::Matrix3d LineOfSightProjector(const Eigen::Vector2d& normalized) {
  const Eigen::Vector3d w(normalized.x(), normalized.y(), 1.0);
  return w * w.transpose() / w.squaredNorm();  // (4.3)
}

double ImageSpaceCost(const Correspondences& c, const pose_math::Pose& T) {
  const Eigen::Matrix3d R = RotationOf(T);
  double sum = 0.0;
  for (int i = 0; i < c.size(); ++i) {
    const Eigen::Vector3d p = R * c.model.col(i) + T.t;
    const double du = c.fx_px * (p.x() / p.z() - c.normalized(0, i));  // (4.1)
    const double dv = c.fy_px * (p.y() / p.z() - c.normalized(1, i));
    sum += du * du + dv * dv;
  }
  return sum / std::max(1, c.size());
}

double ObjectSpaceCost(const Correspondences& c, const pose_math::Pose& T) {
  const Eigen::Matrix3d R = RotationOf(T);
  double sum = 0.0;
  for (int i = 0; i < c.size(); ++i) {
    const Eigen::Vector3d p = R * c.model.col(i) + T.t;
    sum += ((Eigen::Matrix3d::Identity() - LineOfSightProjector(c.normalized.col(i))) * p).squaredNorm();  // (4.2)
  }
  return sum / std::max(1, c.size());
}

double MinDepth(const Eigen::Matrix3Xd& model, const pose_math::Pose& T) {
  const Eigen::Matrix3d R = RotationOf(T);
  double min_z = std::numeric_limits<double>::infinity();
  for (int i = 0; i < model.cols(); ++i) min_z = std::min(min_z, R.row(2).dot(model.col(i)) + T.t.z());
  return min_z;
}

Eigen::Vector3d ModelSpread(const Eigen::Matrix3Xd& model) {
  // Square roots of the scatter matrix's eigenvalues (cheaper than an SVD of 3×n).
  const Eigen::Matrix3Xd centred = model.colwise() - model.rowwise().mean();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(centred * centred.transpose(), Eigen::EigenvaluesOnly);
  return eig.eigenvalues().reverse().cwiseMax(0.0).cwiseSqrt();
}

void EulerRotationDerivatives(double alpha, double beta, double gamma, Eigen::Matrix3d dR[3]) {
  using pose_math::RotX;
  using pose_math::RotY;
  using pose_math::RotZ;
  // d/dθ Rk(θ) = S(ek) Rk(θ) for an elementary rotation about axis k.
  const Eigen::Matrix3d Sx = pose_math::Skew(Eigen::Vector3d::UnitX());
  const Eigen::Matrix3d Sy = pose_math::Skew(Eigen::Vector3d::UnitY());
  const Eigen::Matrix3d Sz = pose_math::Skew(Eigen::Vector3d::UnitZ());
  dR[0] = Sz * RotZ(alpha) * RotY(beta) * RotX(gamma);
  dR[1] = RotZ(alpha) * Sy * RotY(beta) * RotX(gamma);
  dR[2] = RotZ(alpha) * RotY(beta) * Sx * RotX(gamma);
}

}  // namespace cone_tracker
