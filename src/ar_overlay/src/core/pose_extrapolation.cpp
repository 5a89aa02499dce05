#include "ar_overlay/core/pose_extrapolation.h"

#include <algorithm>

namespace ar_overlay {

Eigen::Isometry3d ExtrapolatePose(const Eigen::Isometry3d& T0, double t0_s, const Eigen::Isometry3d& T1, double t1_s,
                                  double t_s, double max_horizon_s) {
  if (!(t1_s > t0_s) || !(t_s > t1_s)) return T1;
  const double s = std::min(t_s - t1_s, std::max(max_horizon_s, 0.0)) / (t1_s - t0_s);
  // Constant velocity: the step from T0 to T1 (rotation R1 R0^T, in the parent
  // frame), repeated s times.
  const Eigen::AngleAxisd step(T1.linear() * T0.linear().transpose());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(step.angle() * s, step.axis()).toRotationMatrix() * T1.linear();
  T.translation() = T1.translation() + s * (T1.translation() - T0.translation());
  return T;
}

}  // namespace ar_overlay
