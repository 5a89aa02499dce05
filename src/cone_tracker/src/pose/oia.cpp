// Orthogonal Iteration Algorithm, Lu & Hager (thesis 4.2.4): alternate the optimal
// translation for a rotation with absolute orientation onto the points
// projected on their lines of sight, lowering the object-space error (4.2).
#include <Eigen/LU>
#include <vector>

#include "cone_tracker/pose/algorithms.h"

namespace cone_tracker {

Estimate OrthogonalIteration(const Correspondences& c, const pose_math::Pose* initial, int max_iterations,
                             double relative_tolerance) {
  const int n = c.size();
  if (n < 4) return Failure("oia needs at least 4 points");
  std::vector<Eigen::Matrix3d> F(n);
  Eigen::Matrix3d F_mean = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i) {
    F[i] = LineOfSightProjector(c.normalized.col(i));  // (4.3)
    F_mean += F[i] / n;
  }
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(Eigen::Matrix3d::Identity() - F_mean);
  if (!lu.isInvertible()) return Failure("oia: I − mean(F) is singular");
  const Eigen::Matrix3d t_factor = lu.inverse() / n;  // (4.46)
  const auto optimal_t = [&](const Eigen::Matrix3d& R) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int i = 0; i < n; ++i) sum += (F[i] - Eigen::Matrix3d::Identity()) * (R * c.model.col(i));
    return Eigen::Vector3d(t_factor * sum);  // (4.46)
  };
  const auto object_error = [&](const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
    double e = 0.0;
    for (int i = 0; i < n; ++i) e += ((F[i] - Eigen::Matrix3d::Identity()) * (R * c.model.col(i) + t)).squaredNorm();
    return e;  // (4.44)
  };

  Eigen::Matrix3d R;
  if (initial != nullptr) {
    R = RotationOf(*initial);
  } else {
    // Lu and Hager's start: align the model with the image rays at unit depth.
    Eigen::Matrix3Xd rays(3, n);
    for (int i = 0; i < n; ++i) rays.col(i) << c.normalized.col(i), 1.0;
    R = RotationOf(AbsoluteOrientationSvd(c.model, rays));
  }
  Eigen::Vector3d t = optimal_t(R);
  double error = object_error(R, t);
  const double scale = (c.model.colwise() - c.model.rowwise().mean()).squaredNorm() + 1e-300;
  Estimate e;
  Eigen::Matrix3Xd projected(3, n);
  for (e.iterations = 0; e.iterations < max_iterations; ++e.iterations) {
    if (error <= 1e-26 * scale) {
      e.converged = true;
      break;
    }
    for (int i = 0; i < n; ++i) projected.col(i) = F[i] * (R * c.model.col(i) + t);  // (4.47)
    R = RotationOf(AbsoluteOrientationSvd(c.model, projected));                      // (4.48) (4.49)
    t = optimal_t(R);
    const double new_error = object_error(R, t);
    const bool small_change = std::abs(error - new_error) <= relative_tolerance * error;
    error = new_error;
    if (small_change) {
      e.converged = true;
      ++e.iterations;
      break;
    }
  }
  e.ok = true;
  e.T_camera_model = PoseFromRt(R, t);
  return e;
}

}  // namespace cone_tracker
