#include "cone_tracker/pose/covariance.h"

#include <Eigen/Cholesky>
#include <stdexcept>

#include "pose_math/covariance.h"

namespace cone_tracker {
namespace {

Eigen::Matrix<double, 2, 3> ProjectionJacobian(const Eigen::Vector3d& p, double fx, double fy) {
  Eigen::Matrix<double, 2, 3> J;
  J << fx / p.z(), 0.0, -fx * p.x() / (p.z() * p.z()), 0.0, fy / p.z(), -fy * p.y() / (p.z() * p.z());
  return J;
}

// d[(F(w) p)]/d(x, y) for w = [x y 1], F = w wᵀ / wᵀw (5.60).
Eigen::Matrix<double, 3, 2> ProjectorDerivative(const Eigen::Vector2d& normalized, const Eigen::Vector3d& p) {
  const Eigen::Vector3d w(normalized.x(), normalized.y(), 1.0);
  const double s = w.squaredNorm(), wp = w.dot(p);
  Eigen::Matrix<double, 3, 2> D;
  for (int k = 0; k < 2; ++k) {
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e(k) = 1.0;
    D.col(k) = (e * wp + w * p(k)) / s - 2.0 * w(k) * w * wp / (s * s);
  }
  return D;
}

void CheckSigma(double sigma_px) {
  if (!(sigma_px > 0.0) || !std::isfinite(sigma_px))
    throw std::invalid_argument("pose covariance: sigma_px must be > 0");
}

}  // namespace

Eigen::Vector2d ImageResidual(const pose_math::Pose& T, const Eigen::Vector3d& model, const Eigen::Vector2d& normalized,
                              double fx_px, double fy_px) {
  const Eigen::Vector3d p = pose_math::Transform(T, model);
  return Eigen::Vector2d(fx_px * (p.x() / p.z() - normalized.x()),
                         fy_px * (p.y() / p.z() - normalized.y()));  // (5.56) (5.57)
}

Eigen::Vector3d ObjectResidual(const pose_math::Pose& T, const Eigen::Vector3d& model,
                               const Eigen::Vector2d& normalized) {
  return (Eigen::Matrix3d::Identity() - LineOfSightProjector(normalized)) *
         pose_math::Transform(T, model);  // (5.63) (5.64) (5.65)
}

Eigen::Matrix<double, 2, 7> ImageJacobianQuat(const pose_math::Pose& T, const Eigen::Vector3d& model, double fx_px,
                                              double fy_px) {
  const Eigen::Matrix<double, 2, 3> P = ProjectionJacobian(pose_math::Transform(T, model), fx_px, fy_px);
  Eigen::Matrix<double, 2, 7> A;  // (5.59)
  A.leftCols<4>() = P * pose_math::RotateJacobianWrtQuat(T.q, model);
  A.rightCols<3>() = P;
  return A;
}

void ObjectJacobiansQuat(const pose_math::Pose& T, const Eigen::Vector3d& model, const Eigen::Vector2d& normalized,
                         Eigen::Matrix<double, 3, 7>* A, Eigen::Matrix<double, 3, 2>* B) {
  const Eigen::Matrix3d IF = Eigen::Matrix3d::Identity() - LineOfSightProjector(normalized);
  A->leftCols<4>() = IF * pose_math::RotateJacobianWrtQuat(T.q, model);  // (5.66)
  A->rightCols<3>() = IF;
  *B = -ProjectorDerivative(normalized, pose_math::Transform(T, model));
}

Eigen::Matrix<double, 2, 6> ImageJacobianEuler(const pose_math::EulerZyx& e, const Eigen::Vector3d& t,
                                               const Eigen::Vector3d& model, double fx_px, double fy_px) {
  Eigen::Matrix3d dR[3];
  EulerRotationDerivatives(e.alpha_rad, e.beta_rad, e.gamma_rad, dR);
  const Eigen::Vector3d p = pose_math::RotationFromEulerZyx(e) * model + t;
  const Eigen::Matrix<double, 2, 3> P = ProjectionJacobian(p, fx_px, fy_px);
  Eigen::Matrix<double, 2, 6> A;
  for (int k = 0; k < 3; ++k) A.col(k) = P * dR[k] * model;
  A.rightCols<3>() = P;
  return A;
}

void ObjectJacobiansEuler(const pose_math::EulerZyx& e, const Eigen::Vector3d& t, const Eigen::Vector3d& model,
                          const Eigen::Vector2d& normalized, Eigen::Matrix<double, 3, 6>* A,
                          Eigen::Matrix<double, 3, 2>* B) {
  Eigen::Matrix3d dR[3];
  EulerRotationDerivatives(e.alpha_rad, e.beta_rad, e.gamma_rad, dR);
  const Eigen::Matrix3d IF = Eigen::Matrix3d::Identity() - LineOfSightProjector(normalized);
  for (int k = 0; k < 3; ++k) A->col(k) = IF * dR[k] * model;
  A->rightCols<3>() = IF;
  *B = -ProjectorDerivative(normalized, pose_math::RotationFromEulerZyx(e) * model + t);
}

// Stacked A (5.49) and block-diagonal (5.55) B COV(n) Bᵀ: σ² I in image space (5.58),
// per-point B_i diag((σ/fu)², (σ/fv)²) B_iᵀ in object space (5.61) (5.62).
template <int Params, typename JacobianFn>
void Stack(const Correspondences& c, ErrorSpace space, double sigma_px, JacobianFn jacobians, Eigen::MatrixXd* A,
           Eigen::MatrixXd* sigma_n) {
  const int n = c.size(), rows = space == ErrorSpace::kImage ? 2 : 3;
  A->resize(rows * n, Params);
  sigma_n->setZero(rows * n, rows * n);
  Eigen::Matrix2d cov_normalized = Eigen::Matrix2d::Zero();
  cov_normalized(0, 0) = std::pow(sigma_px / c.fx_px, 2);
  cov_normalized(1, 1) = std::pow(sigma_px / c.fy_px, 2);
  for (int i = 0; i < n; ++i) {
    Eigen::MatrixXd Ai, Bi;
    jacobians(i, &Ai, &Bi);
    A->middleRows(rows * i, rows) = Ai;
    if (space == ErrorSpace::kImage) {
      sigma_n->block(rows * i, rows * i, rows, rows) = sigma_px * sigma_px * Eigen::Matrix2d::Identity();
    } else {
      sigma_n->block(rows * i, rows * i, rows, rows) = Bi * cov_normalized * Bi.transpose();
    }
  }
}

pose_math::Matrix7d PoseCovarianceQuat(const Correspondences& c, const pose_math::Pose& T, ErrorSpace space,
                                       double sigma_px) {
  CheckSigma(sigma_px);
  Eigen::MatrixXd A, sigma_n;
  Stack<7>(
      c, space, sigma_px,
      [&](int i, Eigen::MatrixXd* Ai, Eigen::MatrixXd* Bi) {
        if (space == ErrorSpace::kImage) {
          *Ai = ImageJacobianQuat(T, c.model.col(i), c.fx_px, c.fy_px);
        } else {
          Eigen::Matrix<double, 3, 7> a;
          Eigen::Matrix<double, 3, 2> b;
          ObjectJacobiansQuat(T, c.model.col(i), c.normalized.col(i), &a, &b);
          *Ai = a;
          *Bi = b;
        }
      },
      &A, &sigma_n);
  return pose_math::ConstrainedPoseCovariance(T.q, A, sigma_n);  // (5.52) with (5.74)
}

Matrix6d PoseCovarianceEuler(const Correspondences& c, const pose_math::Pose& T, ErrorSpace space, double sigma_px) {
  CheckSigma(sigma_px);
  const pose_math::EulerZyx e = pose_math::EulerZyxFromRotation(RotationOf(T));
  Eigen::MatrixXd A, sigma_n;
  Stack<6>(
      c, space, sigma_px,
      [&](int i, Eigen::MatrixXd* Ai, Eigen::MatrixXd* Bi) {
        if (space == ErrorSpace::kImage) {
          *Ai = ImageJacobianEuler(e, T.t, c.model.col(i), c.fx_px, c.fy_px);
        } else {
          Eigen::Matrix<double, 3, 6> a;
          Eigen::Matrix<double, 3, 2> b;
          ObjectJacobiansEuler(e, T.t, c.model.col(i), c.normalized.col(i), &a, &b);
          *Ai = a;
          *Bi = b;
        }
      },
      &A, &sigma_n);
  const Matrix6d normal = A.transpose() * A;
  const Eigen::LDLT<Matrix6d> ldlt(normal);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12 * ldlt.vectorD().maxCoeff()))
    throw std::invalid_argument("PoseCovarianceEuler: pose Jacobian is rank deficient");
  const Eigen::MatrixXd C = ldlt.solve(A.transpose());  // (5.48)
  Matrix6d cov = C * sigma_n * C.transpose();           // (5.52)
  return 0.5 * (cov + cov.transpose());
}

}  // namespace cone_tracker
