// Predicts the camera pose to display time from the two latest estimates at a
// constant velocity (thesis 6.5: render at a fixed rate with the latest
// estimate, so the overlay does not lag the displayed frame).
#pragma once

#include <Eigen/Geometry>

namespace ar_overlay {

// T_a_b at time t from T0 at t0 and T1 at t1 (t1 > t0), with constant linear
// and angular velocity (rotation in the parent frame a). With t1 <= t0 or
// t <= t1 returns T1 unchanged; `max_horizon_s` caps t - t1.
Eigen::Isometry3d ExtrapolatePose(const Eigen::Isometry3d& T0, double t0_s, const Eigen::Isometry3d& T1, double t1_s,
                                  double t_s, double max_horizon_s);

}  // namespace ar_overlay
