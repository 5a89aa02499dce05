#include "pose_math/covariance.h"

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <stdexcept>

namespace pose_math {

Eigen::Matrix<double, 7, 6> QuaternionNullSpace(const Quat& q) {
  Vector7d d = Vector7d::Zero();
  d.head<4>() = NormalizedQuat(q, "QuaternionNullSpace");  // D of (5.69), unit length
  // Householder reflection H = I − 2 v vᵀ / vᵀv mapping d to ∓e1; its other six
  // columns are an orthonormal basis of d⊥ (5.70) (5.71).
  Vector7d v = d;
  v[0] += d[0] >= 0.0 ? 1.0 : -1.0;
  const Matrix7d H = Matrix7d::Identity() - 2.0 * v * v.transpose() / v.squaredNorm();
  return H.rightCols<6>();
}

Matrix7d ConstrainedPoseCovariance(const Quat& q, const Eigen::MatrixXd& A, const Eigen::MatrixXd& sigma_n) {
  if (A.cols() != 7 || sigma_n.rows() != A.rows() || sigma_n.cols() != A.rows()) {
    throw std::invalid_argument("ConstrainedPoseCovariance: A must be m×7 and sigma_n m×m");
  }
  if (!A.allFinite() || !sigma_n.allFinite()) {
    throw std::invalid_argument("ConstrainedPoseCovariance: non-finite Jacobian or noise covariance");
  }
  const Eigen::Matrix<double, 7, 6> N = QuaternionNullSpace(q);
  const Eigen::MatrixXd AN = A * N;
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(AN);
  if (qr.rank() < 6) {
    throw std::invalid_argument("ConstrainedPoseCovariance: pose Jacobian is rank deficient");
  }
  const Eigen::Matrix<double, 6, 6> normal = AN.transpose() * AN;
  const Eigen::MatrixXd C = N * normal.ldlt().solve(AN.transpose());  // (5.74)
  Matrix7d cov = C * sigma_n * C.transpose();                         // (5.52)
  SymmetrizeCovariance(cov);
  return cov;
}

Matrix7d ProjectToTangent(const Quat& q, const Matrix7d& cov7) {
  const Eigen::Matrix<double, 7, 6> N = QuaternionNullSpace(q);
  const Matrix7d P = N * N.transpose();
  return P * cov7 * P.transpose();
}

Eigen::Matrix<double, 4, 3> RotationPerturbationToQuat(const Quat& q) {
  // [1, δθ/2] ⊗ q̂ = q̂ + ½ QR(q̂)[:, 1:3] δθ (2.44).
  return 0.5 * RightMatrix(NormalizedQuat(q, "RotationPerturbationToQuat")).rightCols<3>();
}

Matrix6d CovarianceRosFromThesis(const Quat& q, const Matrix7d& cov7) {
  Eigen::Matrix<double, 6, 7> J = Eigen::Matrix<double, 6, 7>::Zero();
  J.topRightCorner<3, 3>().setIdentity();
  J.bottomLeftCorner<3, 4>() = 4.0 * RotationPerturbationToQuat(q).transpose();
  Matrix6d cov6 = J * cov7 * J.transpose();
  SymmetrizeCovariance(cov6);
  return cov6;
}

Matrix7d CovarianceThesisFromRos(const Quat& q, const Matrix6d& cov6) {
  Eigen::Matrix<double, 7, 6> J = Eigen::Matrix<double, 7, 6>::Zero();
  J.topRightCorner<4, 3>() = RotationPerturbationToQuat(q);
  J.bottomLeftCorner<3, 3>().setIdentity();
  Matrix7d cov7 = J * cov6 * J.transpose();
  SymmetrizeCovariance(cov7);
  return cov7;
}

bool SymmetrizeCovariance(Eigen::Ref<Eigen::MatrixXd> cov) {
  if (!cov.allFinite()) return false;
  // In place, without a temporary: this runs on every message.
  for (Eigen::Index i = 0; i < cov.rows(); ++i) {
    for (Eigen::Index j = i + 1; j < cov.cols(); ++j) {
      const double m = 0.5 * (cov(i, j) + cov(j, i));
      cov(i, j) = m;
      cov(j, i) = m;
    }
  }
  return true;
}

}  // namespace pose_math
