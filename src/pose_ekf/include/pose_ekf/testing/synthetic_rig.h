// A small deterministic simulator of the rig for the pose_ekf tests: a camera
// moving in front of the cones with truth, noisy camera poses at 30 Hz and
// gyro/accelerometer samples at 100 Hz (already in the camera frame).
// Two kinds of motion: a smooth handheld-like sinusoid (accuracy tests) and a
// sample path of the filter's own process model (consistency tests, where the
// filter's assumptions hold by construction).
#pragma once

#include <cstdint>
#include <vector>

#include "pose_ekf/core/measurement.h"

namespace pose_ekf_test {

struct Truth {
  pose_math::Pose T_cones_camera;
  Eigen::Vector3d omega_camera_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_cones_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d a_cones_m_s2 = Eigen::Vector3d::Zero();
};

struct Event {
  double stamp_s = 0.0;
  bool is_camera = false;
  Truth truth;
  pose_ekf::CameraMeasurement camera;
  pose_ekf::ImuMeasurement imu;
};

struct RigSimConfig {
  enum class Motion { kSinusoid, kProcessModel } motion = Motion::kSinusoid;
  double duration_s = 10.0;
  uint32_t seed = 1;
  double camera_sigma_rad = 0.005;  // fixed-axis rotation noise per axis
  double camera_sigma_m = 0.005;
  double gyro_sigma_rad_s = 0.01;
  double accel_sigma_m_s2 = 0.1;
  Eigen::Vector3d gyro_bias_rad_s = Eigen::Vector3d::Zero();
  double gravity_m_s2 = 9.80665;
  double outage_start_s = -1.0, outage_end_s = -1.0;  // no camera frames in [start, end)
  // kProcessModel: random-walk intensities of ω and a.
  double omega_walk_rad_s_per_sqrt_s = 0.5;
  double accel_walk_m_s2_per_sqrt_s = 1.0;
  double motion_scale = 1.0;  // kSinusoid: scales the amplitudes
};

// Events in stamp order (camera first at equal stamps). Camera at 30 Hz and
// IMU at 100 Hz, both starting at t = 0.
std::vector<Event> GenerateRig(const RigSimConfig& config);

// Error of an estimate against truth in ROS order (x y z rx ry rz), with the
// rotation as the fixed-axis (left) perturbation: R_true = exp(S(δθ)) R_est.
Eigen::Matrix<double, 6, 1> PoseError(const pose_math::Pose& truth, const pose_math::Pose& estimate);
// eᵀ Σ6⁻¹ e with Σ6 from the estimate's 7×7 covariance.
double Nees(const pose_math::Pose& truth, const pose_math::PoseWithCovariance& estimate);

// A camera pose at stamp t with independent noise sigma_rad per rotation axis and sigma_m per
// position axis (ROS's 6x6 form, mapped to the filter's 7x7 one).
pose_ekf::CameraMeasurement Camera(double t, const pose_math::Pose& T, double sigma_rad = 0.01, double sigma_m = 0.01);
// A pose away from the identity on every axis, for unit tests.
pose_math::Pose SomePose();

}  // namespace pose_ekf_test

#include <functional>

#include "pose_ekf/core/measurement_buffer.h"

namespace pose_ekf_test {

// Errors of a filter run, evaluated after each IMU sample past warmup_s.
struct RunStats {
  double rms_rotation_rad = 0.0, rms_position_m = 0.0, max_rotation_rad = 0.0;
  double fraction_within_3_sigma = 0.0;  // per axis of the 6 pose errors
  double mean_nees = 0.0;
  int samples = 0;
  std::vector<double> nees;                // one per evaluated sample
  uint64_t camera_gated = 0, reinits = 0;  // the chi-square gate on camera poses, over the whole run
};

// Feeds events to a MeasurementBuffer in the given order and evaluates against
// each event's truth. `in_window(t)` selects the samples to score (all if empty).
RunStats RunFilter(const pose_ekf::EkfConfig& config, const std::vector<Event>& events, double warmup_s,
                   const std::function<bool(double)>& in_window = {});

// The raw camera's errors over the same events, for comparison.
RunStats CameraOnlyStats(const std::vector<Event>& events);

// The chi-square quantile (dof k, probability p), for the NEES intervals;
// Boost.Math, as the tracker's 6.4.1 gate uses.
double ChiSquareQuantile(double k, double p);

}  // namespace pose_ekf_test
