#include "imu_driver/core/gyro_bias.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace imu_driver {

void GyroBiasEstimator::Clear() {
  groups_.clear();
  force_new_ = true;
  total_ = 0;
}

void GyroBiasEstimator::Add(const Eigen::Vector3d& omega, const Eigen::Vector3d& accel) {
  if (!omega.allFinite() || !accel.allFinite()) return;
  bool start_new = force_new_ || groups_.empty();
  if (!start_new && groups_.back().n > 0 && accel.norm() > 0.0) {
    const Eigen::Vector3d mean_dir = groups_.back().a_sum.normalized();
    const double cos_angle = std::clamp(mean_dir.dot(accel.normalized()), -1.0, 1.0);
    start_new = std::acos(cos_angle) > config_.new_orientation_deg * M_PI / 180.0;
  }
  if (start_new) groups_.emplace_back();
  force_new_ = false;
  Accumulator& g = groups_.back();
  ++g.n;
  g.g_sum += omega;
  g.g_sq += omega.cwiseAbs2();
  g.a_sum += accel;
  g.a_sq += accel.cwiseAbs2();
  ++total_;
}

GyroBiasResult GyroBiasEstimator::Compute() const {
  GyroBiasResult r;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), within_ss = Eigen::Vector3d::Zero();
  size_t dof = 0;
  for (const Accumulator& g : groups_) {
    if (g.n < config_.min_samples_per_orientation) continue;  // a transition between poses
    OrientationStats o;
    o.samples = g.n;
    o.gyro_mean_rad_s = g.g_sum / g.n;
    o.accel_mean_m_s2 = g.a_sum / g.n;
    const Eigen::Vector3d g_var = (g.g_sq / g.n - o.gyro_mean_rad_s.cwiseAbs2()).cwiseMax(0.0);
    const Eigen::Vector3d a_var = (g.a_sq / g.n - o.accel_mean_m_s2.cwiseAbs2()).cwiseMax(0.0);
    o.gyro_sigma_rad_s = (g_var * g.n / std::max<size_t>(g.n - 1, 1)).cwiseSqrt();
    o.accel_sigma_m_s2 = a_var.cwiseSqrt();
    if (o.accel_sigma_m_s2.maxCoeff() > config_.max_accel_sigma_m_s2) {
      std::ostringstream m;
      m << "the IMU moved during orientation " << r.orientations.size() + 1 << " (accel sigma "
        << o.accel_sigma_m_s2.maxCoeff() << " m/s^2 > " << config_.max_accel_sigma_m_s2 << ")";
      r.message = m.str();
      return r;
    }
    sum += g.g_sum;
    within_ss += g_var * g.n;
    dof += g.n - 1;
    r.samples += g.n;
    r.orientations.push_back(o);
  }
  if (r.orientations.empty() || dof == 0) {
    std::ostringstream m;
    m << "not enough static data: " << total_ << " samples, need " << config_.min_samples_per_orientation
      << " at one orientation at least";
    r.message = m.str();
    return r;
  }
  r.bias_rad_s = sum / r.samples;
  r.sigma_rad_s = (within_ss / dof).cwiseSqrt();
  if (r.bias_rad_s.cwiseAbs().maxCoeff() > config_.max_bias_rad_s) {
    std::ostringstream m;
    m << "the IMU seems to be turning: mean rate [" << r.bias_rad_s.transpose() << "] rad/s exceeds the "
      << config_.max_bias_rad_s << " rad/s a bias can be";
    r.message = m.str();
    return r;
  }
  r.ok = true;
  std::ostringstream m;
  m << "bias [" << r.bias_rad_s.transpose() << "] rad/s, sigma [" << r.sigma_rad_s.transpose() << "] rad/s from "
    << r.samples << " samples at " << r.orientations.size() << " orientation(s)";
  r.message = m.str();
  return r;
}

}  // namespace imu_driver
