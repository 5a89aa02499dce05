#include "null_space.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <cmath>

#include "pose_math/quaternion.h"
#include "pose_math/rotation.h"

namespace cone_tracker {

Eigen::MatrixXd MeasurementMatrix(const Correspondences& c, const std::vector<PointMap>& maps, ErrorSpace space) {
  const int n = c.size();
  const int rows_per_point = space == ErrorSpace::kImage ? 2 : 3;
  Eigen::MatrixXd M(rows_per_point * n, 12);
  for (int i = 0; i < n; ++i) {
    const double x = c.normalized(0, i), y = c.normalized(1, i);
    if (space == ErrorSpace::kImage) {
      // e_u = fu X + (u0 − u) Z = fu (X − x Z) (4.50) (4.51).
      M.row(2 * i) = c.fx_px * (maps[i].row(0) - x * maps[i].row(2));
      M.row(2 * i + 1) = c.fy_px * (maps[i].row(1) - y * maps[i].row(2));
    } else {
      // e = (F_i − I) p_c (4.52) (4.53) (4.54).
      M.middleRows<3>(3 * i) = (LineOfSightProjector(c.normalized.col(i)) - Eigen::Matrix3d::Identity()) * maps[i];
    }
  }
  return M;
}

NullSpace DecomposeMeasurementMatrix(const Eigen::MatrixXd& M) {
  const Matrix12d normal = M.transpose() * M;
  const Eigen::SelfAdjointEigenSolver<Matrix12d> eig(normal);  // (4.73), eigenvalues ascending
  NullSpace ns;
  ns.V = eig.eigenvectors();
  // MᵀM = V S² Vᵀ = (S Vᵀ)ᵀ(S Vᵀ): M̂ = S Vᵀ (4.80), 12×12 for any number of points.
  ns.reduced = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * ns.V.transpose();
  return ns;
}

Eigen::Matrix3Xd CameraPoints(const std::vector<PointMap>& maps, const Vector12d& v) {
  Eigen::Matrix3Xd points(3, maps.size());
  for (size_t i = 0; i < maps.size(); ++i) points.col(i) = maps[i] * v;
  return points;
}

Estimate ScaleAndAlign(const Eigen::Matrix3Xd& model, const Eigen::Matrix3Xd& unscaled_camera) {
  const Eigen::Vector3d S_mean = unscaled_camera.rowwise().mean();  // (4.76)
  const Eigen::Vector3d P_mean = model.rowwise().mean();
  const double Cd = (unscaled_camera.colwise() - S_mean).squaredNorm();  // (4.77)
  const double Md = (model.colwise() - P_mean).squaredNorm();
  if (!(Cd > 0.0) || !std::isfinite(Cd)) return Failure("null-space solution has zero spread");
  const double beta = (S_mean.z() < 0.0 ? -1.0 : 1.0) * std::sqrt(Md / Cd);  // (4.78)
  Estimate e;
  e.ok = true;
  e.converged = true;
  e.T_camera_model = AbsoluteOrientationSvd(model, beta * unscaled_camera);  // (4.79)
  return e;
}

void LeftEulerDerivatives(const Eigen::Matrix3d& R, Eigen::Matrix3d dR[3]) {
  dR[0] = pose_math::Skew(Eigen::Vector3d::UnitZ()) * R;
  dR[1] = pose_math::Skew(Eigen::Vector3d::UnitY()) * R;
  dR[2] = pose_math::Skew(Eigen::Vector3d::UnitX()) * R;
}

GaussNewtonResult NullSpaceGaussNewton(const Matrix12d& reduced, NullSpaceParam param, const Eigen::Matrix3d& R0,
                                       const Eigen::Vector3d& t0, int max_iterations) {
  GaussNewtonResult r{R0, t0, 0, false};
  Vector12d v;
  Eigen::Matrix<double, 12, 6> dv;
  Eigen::Matrix3d dR[3];
  LeftEulerDerivatives(R0, dR);
  const auto cost_of = [&](const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
    Vector12d vv;
    param(R, t, dR, &vv, nullptr);
    return (reduced * vv).squaredNorm();
  };
  double cost = cost_of(r.R, r.t);
  for (; r.iterations < max_iterations; ++r.iterations) {
    LeftEulerDerivatives(r.R, dR);
    param(r.R, r.t, dR, &v, &dv);
    const Vector12d f = reduced * v;                                                                // (4.85)
    const Eigen::Matrix<double, 12, 6> J = reduced * dv;                                            // (4.86)
    const Eigen::Matrix<double, 6, 1> step = -(J.transpose() * J).ldlt().solve(J.transpose() * f);  // (4.87)
    if (!step.allFinite()) break;
    // Halve the step until the cost drops (plain Gauss–Newton may overshoot).
    double scale = 1.0;
    bool accepted = false;
    for (int k = 0; k < 8 && !accepted; ++k, scale *= 0.5) {
      const Eigen::Matrix3d R =
          pose_math::RotZ(scale * step(0)) * pose_math::RotY(scale * step(1)) * pose_math::RotX(scale * step(2)) * r.R;
      const Eigen::Vector3d t = r.t + scale * step.tail<3>();
      const double new_cost = cost_of(R, t);
      if (new_cost <= cost) {
        r.R = R;
        r.t = t;
        cost = new_cost;
        accepted = true;
      }
    }
    const double size = step.head<3>().norm() + step.tail<3>().norm() / std::max(1e-9, r.t.norm());
    if (!accepted || size < 1e-12) {
      r.converged = true;  // no further decrease possible: a (local) minimum
      ++r.iterations;
      break;
    }
  }
  return r;
}

bool Barycentric(const Eigen::Matrix<double, 3, 4>& vertices, const Eigen::Matrix3Xd& model, Eigen::Matrix4Xd* alpha) {
  Eigen::Matrix4d S;
  S.topRows<3>() = vertices;
  S.row(3).setOnes();
  const Eigen::FullPivLU<Eigen::Matrix4d> lu(S);
  if (!lu.isInvertible()) return false;
  Eigen::Matrix4Xd P(4, model.cols());
  P.topRows<3>() = model;
  P.row(3).setOnes();
  *alpha = lu.solve(P);  // (4.91)
  return true;
}

std::vector<PointMap> SimplexPointMaps(const Eigen::Matrix4Xd& alpha) {
  std::vector<PointMap> maps(alpha.cols());
  for (int i = 0; i < alpha.cols(); ++i) {
    for (int j = 0; j < 4; ++j) maps[i].block<3, 3>(0, 3 * j) = alpha(j, i) * Eigen::Matrix3d::Identity();
  }
  return maps;
}

}  // namespace cone_tracker
