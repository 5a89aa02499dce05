// Static gyro bias and noise (thesis 3.2.1): with the IMU still, the gyro reads
// ω' = ω + bias + v_gyro with ω = 0 (3.27), so the per-axis mean of many static
// samples is the bias and their standard deviation is σ_gyro. Samples from
// several orientations are pooled; the per-orientation means are kept to show
// that the bias does not depend on orientation (the thesis's observation).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

namespace imu_driver {

struct GyroBiasConfig {
  size_t min_samples_per_orientation = 100;
  // Stillness test: if an orientation's accelerometer σ exceeds this, the
  // unit moved while recording and the result is refused.
  double max_accel_sigma_m_s2 = 0.5;
  // Orientations are told apart by the direction of gravity: a new one starts
  // when the mean accel direction turns by more than this.
  double new_orientation_deg = 20.0;
  // A "bias" above this is a turning IMU (a constant rotation about gravity
  // leaves the accelerometer still): refused. 0.1 rad/s is 5.7 deg/s.
  double max_bias_rad_s = 0.1;
};

struct OrientationStats {
  size_t samples = 0;
  Eigen::Vector3d gyro_mean_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_sigma_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_mean_m_s2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_sigma_m_s2 = Eigen::Vector3d::Zero();
};

struct GyroBiasResult {
  bool ok = false;
  std::string message;  // why not, or a summary
  Eigen::Vector3d bias_rad_s = Eigen::Vector3d::Zero();
  // Pooled within-orientation σ: the noise after the bias is removed.
  Eigen::Vector3d sigma_rad_s = Eigen::Vector3d::Zero();
  size_t samples = 0;
  std::vector<OrientationStats> orientations;
};

class GyroBiasEstimator {
 public:
  explicit GyroBiasEstimator(const GyroBiasConfig& config = GyroBiasConfig()) : config_(config) {}

  // One static sample. Call NewOrientation() between poses, or let the
  // gravity direction split them automatically.
  void Add(const Eigen::Vector3d& omega_imu_rad_s, const Eigen::Vector3d& accel_imu_m_s2);
  void NewOrientation() { force_new_ = true; }
  void Clear();
  size_t samples() const { return total_; }

  GyroBiasResult Compute() const;

 private:
  struct Accumulator {
    size_t n = 0;
    Eigen::Vector3d g_sum = Eigen::Vector3d::Zero(), g_sq = Eigen::Vector3d::Zero();
    Eigen::Vector3d a_sum = Eigen::Vector3d::Zero(), a_sq = Eigen::Vector3d::Zero();
  };
  GyroBiasConfig config_;
  std::vector<Accumulator> groups_;
  bool force_new_ = true;
  size_t total_ = 0;
};

}  // namespace imu_driver
