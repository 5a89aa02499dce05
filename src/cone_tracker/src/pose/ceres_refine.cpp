// Ceres refinement of the image-space reprojection error (4.1) over the pose,
// the quaternion on Ceres's QuaternionManifold (Ceres's [w x y z] order is the
// thesis's [q0 qx qy qz]), with an optional Huber loss.
#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <ceres/tiny_solver.h>

#include "cone_tracker/pose/algorithms.h"
#include "pose_math/quaternion.h"
#include "pose_math/rotation.h"

namespace cone_tracker {
namespace {

struct Reprojection {
  Reprojection(const Eigen::Vector3d& model, const Eigen::Vector2d& normalized, double fx, double fy)
      : model_(model), normalized_(normalized), fx_(fx), fy_(fy) {}
  template <typename T>
  bool operator()(const T* q, const T* t, T* residual) const {
    const T p_m[3] = {T(model_.x()), T(model_.y()), T(model_.z())};
    T p_c[3];
    ceres::UnitQuaternionRotatePoint(q, p_m, p_c);
    p_c[0] += t[0];
    p_c[1] += t[1];
    p_c[2] += t[2];
    residual[0] = T(fx_) * (p_c[0] / p_c[2] - T(normalized_.x()));
    residual[1] = T(fy_) * (p_c[1] / p_c[2] - T(normalized_.y()));
    return true;
  }
  Eigen::Vector3d model_;
  Eigen::Vector2d normalized_;
  double fx_, fy_;
};

// The same residual for ceres::TinySolver over a local chart of the quaternion
// manifold: x = (θ, t) with R = exp(S(θ)) R0. TinySolver re-linearises at the
// current x on every iteration, so the rotation columns must be exact there:
// d(R p)/dθ = −S(R p) J_l(θ), J_l the left Jacobian of SO(3). (With −S(R p)
// alone, exact only at θ = 0, the stationary points are the same but the
// Levenberg–Marquardt steps are wrong away from the start: from a linear start
// several degrees off it stalls short of the minimum.)
// J_l(θ) = I + (1 − cos|θ|)/|θ|² S(θ) + (|θ| − sin|θ|)/|θ|³ S(θ)², so that
// exp(S(θ + δ)) ≈ exp(S(J_l δ)) exp(S(θ)); Taylor series near θ = 0.
// (Not in pose_math, which has no SO(3) Jacobians; kept here, its one user.)
Eigen::Matrix3d LeftJacobian(const Eigen::Vector3d& theta) {
  const double a2 = theta.squaredNorm(), a = std::sqrt(a2);
  const Eigen::Matrix3d S = pose_math::Skew(theta);
  const double c1 = a < 1e-4 ? 0.5 - a2 / 24.0 : (1.0 - std::cos(a)) / a2;
  const double c2 = a < 1e-4 ? 1.0 / 6.0 - a2 / 120.0 : (a - std::sin(a)) / (a2 * a);
  return Eigen::Matrix3d::Identity() + c1 * S + c2 * S * S;
}

struct ChartReprojection {
  using Scalar = double;
  enum { NUM_RESIDUALS = Eigen::Dynamic, NUM_PARAMETERS = 6 };
  bool operator()(const double* x, double* residual, double* jacobian) const {
    const Eigen::Map<const Eigen::Vector3d> rotation_vector(x), t(x + 3);
    const double angle = rotation_vector.norm();
    const Eigen::Matrix3d R = angle > 0.0 ? Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix()
                                          : Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d J_left = LeftJacobian(rotation_vector);
    const int m = NumResiduals();
    for (int i = 0; i < rotated.cols(); ++i) {
      const Eigen::Vector3d Rp = R * rotated.col(i);
      const Eigen::Vector3d p = Rp + t;
      const double iz = 1.0 / p.z();
      residual[2 * i] = fx * (p.x() * iz - normalized(0, i));  // (4.1)
      residual[2 * i + 1] = fy * (p.y() * iz - normalized(1, i));
      if (jacobian == nullptr) continue;
      Eigen::Matrix<double, 2, 3> P;
      P << fx * iz, 0.0, -fx * p.x() * iz * iz, 0.0, fy * iz, -fy * p.y() * iz * iz;
      const Eigen::Matrix<double, 2, 3> Jr = -P * pose_math::Skew(Rp) * J_left;
      for (int k = 0; k < 3; ++k) {
        jacobian[2 * i + k * m] = Jr(0, k);
        jacobian[2 * i + 1 + k * m] = Jr(1, k);
        jacobian[2 * i + (k + 3) * m] = P(0, k);
        jacobian[2 * i + 1 + (k + 3) * m] = P(1, k);
      }
    }
    return true;
  }
  int NumResiduals() const { return 2 * static_cast<int>(rotated.cols()); }
  Eigen::Matrix3Xd rotated;  // R0 p_m
  Eigen::Matrix2Xd normalized;
  double fx, fy;
};

ChartReprojection MakeChart(const Correspondences& c, const pose_math::Pose& origin) {
  ChartReprojection f;
  f.rotated = RotationOf(origin) * c.model;
  f.normalized = c.normalized;
  f.fx = c.fx_px;
  f.fy = c.fy_px;
  return f;
}

}  // namespace

void ChartResidualsAndJacobian(const Correspondences& c, const pose_math::Pose& origin,
                               const Eigen::Matrix<double, 6, 1>& x, Eigen::VectorXd* residuals,
                               Eigen::MatrixXd* jacobian) {
  const ChartReprojection f = MakeChart(c, origin);
  residuals->resize(f.NumResiduals());
  jacobian->resize(f.NumResiduals(), 6);  // column-major, as TinySolver fills it
  f(x.data(), residuals->data(), jacobian->data());
}

Estimate TinyCeresRefine(const Correspondences& c, const pose_math::Pose& initial, int max_iterations) {
  if (c.size() < 4) return Failure("refinement needs at least 4 points");
  const ChartReprojection f = MakeChart(c, initial);
  ceres::TinySolver<ChartReprojection> solver;
  solver.options.max_num_iterations = max_iterations;
  solver.options.gradient_tolerance = 1e-14;
  solver.options.parameter_tolerance = 1e-11;
  solver.options.function_tolerance = 1e-12;
  solver.options.cost_threshold = 1e-24;
  Eigen::Matrix<double, 6, 1> x;
  x << 0, 0, 0, initial.t;
  const auto& summary = solver.Solve(f, &x);
  if (!x.allFinite()) return Failure("refinement diverged");
  Estimate e;
  e.ok = true;
  e.T_camera_model.q = pose_math::CanonicalSign(
      pose_math::NormalizedQuat(pose_math::Multiply(pose_math::QuatFromRotationVector(x.head<3>()), initial.q)));
  e.T_camera_model.t = x.tail<3>();
  e.iterations = summary.iterations;
  e.converged = summary.status != ceres::TinySolver<ChartReprojection>::HIT_MAX_ITERATIONS;
  return e;
}

Estimate CeresRefine(const Correspondences& c, const pose_math::Pose& initial, bool robust_loss,
                     double huber_threshold_px, int max_iterations) {
  if (c.size() < 4) return Failure("ceres refinement needs at least 4 points");
  double q[4], t[3];
  const pose_math::Quat q0 = pose_math::NormalizedQuat(initial.q, "CeresRefine");
  for (int k = 0; k < 4; ++k) q[k] = q0[k];
  for (int k = 0; k < 3; ++k) t[k] = initial.t[k];

  ceres::Problem::Options problem_options;
  ceres::Problem problem(problem_options);
  for (int i = 0; i < c.size(); ++i) {
    auto* cost = new ceres::AutoDiffCostFunction<Reprojection, 2, 4, 3>(
        new Reprojection(c.model.col(i), c.normalized.col(i), c.fx_px, c.fy_px));
    problem.AddResidualBlock(cost, robust_loss ? new ceres::HuberLoss(huber_threshold_px) : nullptr, q, t);
  }
  problem.SetManifold(q, new ceres::QuaternionManifold);

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = max_iterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  options.function_tolerance = 1e-14;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);

  Estimate e;
  e.ok = summary.IsSolutionUsable();
  if (!e.ok) return Failure("ceres: " + summary.message);
  e.T_camera_model.q = pose_math::CanonicalSign(pose_math::NormalizedQuat(pose_math::Quat(q[0], q[1], q[2], q[3])));
  e.T_camera_model.t = Eigen::Vector3d(t[0], t[1], t[2]);
  e.iterations = static_cast<int>(summary.iterations.size());
  e.converged = summary.termination_type == ceres::CONVERGENCE;
  return e;
}

}  // namespace cone_tracker
