// The quaternion EKF of thesis chapter 5, without buffering or ROS.
// Call order: Initialize() from a camera pose, then Predict(t) and one of the
// Update*() at each measurement's stamp. MeasurementBuffer does that in stamp order.
#pragma once

#include <vector>

#include "pose_ekf/core/cone_measurement.h"
#include "pose_ekf/core/config.h"
#include "pose_ekf/core/measurement.h"
#include "pose_ekf/core/process_model.h"
#include "pose_math/pose.h"

namespace pose_ekf {

enum class UpdateResult { kApplied, kDisabled, kGated, kRejectedNonFinite, kNumericalFailure };
const char* ToString(UpdateResult r);

// Everything needed to go back in time (buffer replay, 6.3).
struct FilterState {
  double stamp_s = 0.0;
  StateVector x;
  StateMatrix P;
  // The lever arm's α (not a state): the change of the estimated ω between the last two gyro updates.
  Eigen::Vector3d omega_at_last_gyro_rad_s = Eigen::Vector3d::Zero();
  double last_gyro_stamp_s = -1.0;  // < 0: none yet
  Eigen::Vector3d alpha_camera_rad_s2 = Eigen::Vector3d::Zero();
  double last_imu_stamp_s = -1.0;     // the last IMU sample's stamp (gyro_is_centred_interval_mean); < 0: none
  double omega_walk_pending_s = 0.0;  // omega_walk_at_gyro: prediction time whose ω random walk is not in P yet
  FusedConeView fused_view;           // the last fused cone frame's pixels (EkfConfig::cone_repeat_px)
};

class EkfCore {
 public:
  // Throws std::invalid_argument naming the member if config.Validate() fails.
  explicit EkfCore(const EkfConfig& config);

  // Noise and switches may change at run time; the state size may not
  // (estimate_gyro_bias and estimate_accel_bias changes take effect at the next Initialize()).
  void SetConfig(const EkfConfig& config);
  const EkfConfig& config() const { return config_; }

  // From the first accepted camera pose and its covariance. Returns false (and
  // stays uninitialised) for a non-finite measurement.
  bool Initialize(const CameraMeasurement& m);
  // IMU-only start (EkfConfig::init_from_gravity): roll and pitch from the
  // specific force, heading 0, position 0. False unless |a| is within the
  // accelerometer gate of g (or finite, with the gate off).
  bool InitializeFromGravity(double stamp_s, const Eigen::Vector3d& accel_camera_m_s2);
  void Reset() { initialized_ = false; }
  bool initialized() const { return initialized_; }

  // Time update ((5.20), and (5.14) with F (5.22) and Q (5.23)) to stamp_s;
  // gaps longer than max_predict_step_s are sub-stepped. A stamp before the
  // current one is ignored (the buffer rewinds).
  void Predict(double stamp_s);

  // Measurement updates (5.15) (5.16) (5.17) of the camera (5.24), gyro (5.27)
  // and accelerometer (5.30) at the current time. nis, if given, receives the
  // normalised innovation squared yᵀ S⁻¹ y. A camera pose outside the
  // chi-square gate (EkfConfig::camera_gate_chi2) returns kGated and
  // leaves the state alone; gate_chi2, if given, receives its statistic (the
  // squared Mahalanobis distance on 6 dof, see CameraGateStatistic).
  UpdateResult UpdateCamera(const CameraMeasurement& m, double* nis = nullptr, double* gate_chi2 = nullptr);
  UpdateResult UpdateGyro(const ImuMeasurement& m, double* nis = nullptr);
  UpdateResult UpdateAccel(const ImuMeasurement& m, double* nis = nullptr);

  // The tightly coupled camera update (cone_measurement.h, cone_update.cpp): the frame's cones in
  // sequence, each gated on yᵀ S⁻¹ y against chi2(6) at cone_gate_probability, then the fused
  // cones' joint NIS against chi2(6 k) at cone_joint_probability (the worst cone is dropped and the
  // rest retried). kApplied if at least min_cones cones were fused together, kGated if the gates (or a
  // prediction behind the camera) left fewer; the state is unchanged unless kApplied. min_cones > 1 is
  // re-acquisition (MeasurementBuffer, EkfConfig::reacquire_min_cones): a lone cone is not trusted then.
  // A frame that repeats the last fused frame's view (EkfConfig::cone_repeat_px, RepeatsView) is not fused: it
  // returns kDisabled with result->repeated, after UpdateStill (cone_repeat_sigma_v_m_s, cone_repeat_sigma_omega_rad_s)
  // of the camera it shows still.
  UpdateResult UpdateCones(const ConeFrame& f, ConeFrameResult* result = nullptr, int min_cones = 1);
  // The camera's velocity and angular rate are zero, to these sigmas per axis (pseudo-measurements; kDisabled
  // unless both are positive).
  UpdateResult UpdateStill(double sigma_v_m_s, double sigma_omega_rad_s);
  double cone_gate_chi2() const { return cone_gate_chi2_; }
  double cone_joint_chi2(int cones) const;

  // The camera gate's threshold on the 6-dof statistic (infinite when off).
  double camera_gate_chi2() const { return camera_gate_chi2_; }
  static constexpr int kCameraGateDof = 6;  // 3 rotation + 3 position

  // The stamp of the IMU sample being applied (the measurement buffer, gyro_is_centred_interval_mean).
  void NoteImuStamp(double stamp_s) { s_.last_imu_stamp_s = stamp_s; }
  const FilterState& state() const { return s_; }
  void Restore(const FilterState& s) { s_ = s; }

  // Camera in cones, T_cones_camera, with its 7x7 (q, p) covariance.
  pose_math::PoseWithCovariance Pose() const;
  Eigen::Vector3d omega_camera_rad_s() const { return s_.x.segment<3>(kW); }
  Eigen::Vector3d v_cones_m_s() const { return s_.x.segment<3>(kV); }
  Eigen::Vector3d gyro_bias_rad_s() const;
  Eigen::Vector3d accel_bias_m_s2() const;  // zero unless estimate_accel_bias

 private:
  template <int M>
  UpdateResult Update(const Eigen::Matrix<double, M, 1>& residual,
                      const Eigen::Matrix<double, M, Eigen::Dynamic, 0, M, kMaxStates>& H,
                      const Eigen::Matrix<double, M, M>& R, double* nis);
  void PredictStep(double dt_s);
  void InitializeUnmeasured(int n);
  void SetConeGates();  // cone_update.cpp
  // One cone's (iterated) update from the current state (cone_update.cpp); the state is unchanged unless applied.
  UpdateResult UpdateCone(const ConeObservation& o, const PinholeIntrinsics& K, double* nis);
  void NoteAngularAcceleration();
  void AddOmegaWalk();  // omega_walk_at_gyro: ω's random walk for omega_walk_pending_s into P

  EkfConfig config_;
  double camera_gate_chi2_ = 0.0;  // config_.camera_gate_chi2, infinite when off
  static constexpr int kConeJointTableSize = 8;
  double cone_gate_chi2_ = 0.0;          // chi2(6) at cone_gate_probability
  std::vector<double> cone_joint_chi2_;  // chi2(6 k) at cone_joint_probability, k = 1..
  FilterState s_;
  bool initialized_ = false;
  // The bias states of the current state vector (fixed at Initialize()).
  bool has_gyro_bias_ = false, has_accel_bias_ = false;
};

}  // namespace pose_ekf
