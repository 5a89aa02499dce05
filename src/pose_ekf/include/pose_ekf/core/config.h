// Configuration of the pose EKF (thesis chapter 5) and its measurement buffer (section 6.3).
// One struct, units in the names. The ROS adapter fills it from parameters
// (LoadConfig) and the core validates it (Validate) so bad values are refused
// with a message naming the member.
#pragma once

#include <string>

namespace pose_ekf {

enum class QuatIntegration { kFirstOrder, kExact };  // (2.70) (thesis default) or (2.71)
// A camera-IMU lever arm longer than this is a broken calibration (a rig is centimetres across).
constexpr double kMaxLeverArmM = 1.0;
// omega_walk_at_gyro: the longest time ω's random walk waits for a gyro sample (10 periods at 100 Hz).
constexpr double kMaxOmegaWalkDeferS = 0.1;

enum class AccelMode { kOff, kOrientation, kPositionAndOrientation };  // h, H: (5.36) (5.37) / (5.39) (5.40)
// What corrects the filter from the camera: the tracker's cone observations, one update per cone
// (cone_measurement.h), or its single-frame pose (5.24), the thesis's loosely coupled path.
enum class CameraUpdate { kCones, kPose };

struct EkfConfig {
  // Process noise, variance per second (5.23) expressed as sigma per sqrt(second).
  double sigma_q_per_sqrt_s = 1e-3;           // quaternion (unitless)
  double sigma_omega_rad_s_per_sqrt_s = 3.0;  // angular velocity random walk
  double sigma_p_m_per_sqrt_s = 1e-3;
  double sigma_v_m_s_per_sqrt_s = 0.05;
  double sigma_a_m_s2_per_sqrt_s = 6.0;  // acceleration random walk (jerk)
  double sigma_gyro_bias_rad_s_per_sqrt_s = 1e-4;

  // Measurement noise of the IMU (constant, section 5.6 first paragraph).
  double sigma_gyro_rad_s = 0.01;
  double sigma_accel_m_s2 = 0.2;
  bool use_message_imu_covariance = false;  // prefer the sensor_msgs/Imu covariances when given

  // Which updates run (the thesis's GUI switches).
  bool use_camera = true;
  bool use_gyro = true;
  // Position+orientation (5.39) (5.40) by default: it models the camera's own
  // acceleration, while orientation-only ((5.36) (5.37), the thesis's choice) tilts
  // the estimate by a/g under handheld motion the gate cannot see (a horizontal
  // 1 m/s² changes |z| by only 0.05 m/s²). Measured in test_accuracy.
  AccelMode accel_mode = AccelMode::kPositionAndOrientation;
  double gravity_m_s2 = 9.80665;
  double accel_gate_m_s2 = 0.5;  // (5.34): use the accelerometer only when | |z| - g | <= gate; <= 0 disables

  // true: a gyro sample stamped t is the mean rate over the interval since the
  // previous IMU sample (a sampled, low-pass-filtered MEMS gyro; rig_sim's
  // Crista model; BROAD, whose Madgwick results integrate it that way), so it
  // is applied before the time update over that interval and (5.21)
  // integrates the rate measured over it. false (the thesis's order, (5.19) then
  // (5.27)): applied after, as the rate at t, which the quaternion then lags by
  // one IMU period unless the samples are stamped at the interval's midpoint
  // (test_rig_sim does that). Measured in test_broad and the README.
  bool gyro_is_interval_mean = false;
  // true: a gyro sample stamped t is the mean rate over the period CENTRED on t (REP-145 midpoint
  // stamps: rig_sim's messages, imu_driver's stamp_at_interval_midpoint), so it is applied at the
  // midpoint between the previous IMU stamp and t, after predicting to there with the previous rate.
  // Either of the two orders above lags or leads the orientation by half a period (5 ms at 100 Hz:
  // 0.7 deg at 2.4 rad/s on rig_sim's handheld, measured in the README). Excludes gyro_is_interval_mean.
  bool gyro_is_centred_interval_mean = false;
  // true (with use_gyro): ω's random walk (sigma_omega_rad_s_per_sqrt_s) is added at each gyro sample, for the time
  // since the last one, instead of at every prediction step. ω is then constant between samples, as a gyro that
  // averages over its period sees it. Spread over the steps, the walk also reaches q between a sample and the next
  // (the prediction integrates ω), a random walk of q beyond the gyro's own noise that hides the gyro bias from the
  // camera (README, "camera outages"). A gap over kMaxOmegaWalkDeferS adds it as before. Needs
  // gyro_is_interval_mean or gyro_is_centred_interval_mean: with point samples the rate does change between them.
  bool omega_walk_at_gyro = false;

  // Camera gate, beyond the thesis (its vision thread gates in image space,
  // 6.4.1): a camera pose whose squared Mahalanobis distance under the filter's
  // own S = H P Hᵀ + R, on the pose's 6 dof (chi-square distributed for a
  // consistent filter), exceeds this is not fused. 0 disables it. A gross-error
  // gate: the chi2(6) quantile at 0.9999 is 27.9, but good poses reach 100-300
  // against the filter in its thesis configurations (README).
  double camera_gate_chi2 = 1000.0;
  // This many gated camera poses in a row mean the filter, not the camera, is
  // wrong: the filter re-initialises from the last of them, like its first
  // initialisation. 0 never re-initialises.
  int reinit_after_rejections = 15;  // 0.5 s at 30 Hz

  // Tightly coupled camera updates (cone_measurement.h), beyond the thesis. kCones: a frame's cone
  // observations are fused and its pose is not (fused once); a pose whose frame brought no
  // observations is fused as with kPose; poses still initialise the filter, and re-initialise it
  // (MeasurementBuffer) after reinit_after_rejections rejected cone frames in a row or when the
  // position sigma exceeds reacquire_sigma_p_m. kPose: observations are ignored.
  // The core's default is kPose, the thesis's path; rig_sim's configuration uses kCones (README,
  // "Re-acquisition": measured on rig_sim, not yet on a real bag with truth).
  CameraUpdate camera_update = CameraUpdate::kPose;
  // Per cone: yᵀ S⁻¹ y (beyond the gate: the cone's iterated fit, ConeFitCost) against chi2(4) at this probability;
  // 1 = off.
  double cone_gate_probability = 0.9999;
  double cone_joint_probability = 0.9999;  // per frame: the fused cones' NIS sum against chi2(4 k); 1 = off
  double reacquire_sigma_p_m = 0.5;        // largest position sigma before a pose re-initialises; 0 = never
  // While re-acquiring (the same test: position sigma above reacquire_sigma_p_m, or
  // reinit_after_rejections cone frames rejected in a row) a cone frame is fused only if at least this
  // many of its cones pass the gates together: after a long outage the filter's prediction cannot tell
  // which layout cone a lone detection is (README, "Re-acquisition"); two or more are checked jointly.
  int reacquire_min_cones = 1;
  // A frame with one cone is not fused when another layout cone (ConeFrame::layout) fits its pixels
  // within this much (chi-square, 4 dof, the filter's own S) of the cone it was associated with: the
  // filter's own check of the tracker's association, scaled by its covariance (README,
  // "Re-acquisition"). 0 = off.
  double cone_ambiguity_margin = 9.0;
  // How the statistics of that test are taken: the fit of each layout cone to the pixels, iterated
  // (ConeFitCost, Gauss-Newton on the prior and the pinhole) so that a rival that needs a large pose
  // correction is judged by that correction's Mahalanobis distance, not by the linearisation at the
  // prediction (which scores a cone 1.5 m away ~80 where the fit gives ~1). 0 = first order.
  int cone_ambiguity_iterations = 5;
  // Negative information in that test: a reading of the lone cone whose fitted pose puts another layout cone
  // in plain view, or partly in view where the image has no orange (rig_model/cone_view.h), where the frame has
  // none costs this much more per such cone, -2 ln(1 - P_D) (README, "Negative information"). Needs the image size
  // (ConeFrame::width_px; the part view also ConeFrame::orange_px); 0 = off.
  double cone_miss_cost = 0.0;
  // And per orange box of the frame (ConeFrame::orange_px) that the reading's fitted pose puts no layout cone near, nor
  // any of the frame's cones as measured (rig_model::UnexplainedOrange): orange left to clutter; 0: off.
  double cone_unexplained_cost = 0.0;
  // Each fused cone's update is iterated (the iterated EKF: relinearised at the updated state) up to
  // this many more times, while the pixels the updated state predicts differ from the linearisation's
  // by more than a tenth of a pixel. Tracked, one update suffices (the check costs one projection).
  // Re-acquiring from a prior 0.5-2 m off, one linearisation leaves ~0.1 m with a covariance claiming
  // ~0.03 m, and the next cone's NIS, taken at that state, may fail the frame's joint check. The
  // per-cone gates keep their first-order statistics at the prior. 0 = the EKF's single update.
  int cone_update_iterations = 3;
  // A cone frame that shows only cones of the last fused frame, each of its points less than this many pixels
  // from where that frame had it, is the same view again: its pixel errors are that frame's errors (the segmentation
  // of a still image repeats itself), so fusing it as independent makes the filter sure of them, and the biases
  // learn them (README, "Repeated views"). Such a frame is not fused, unless cone_repeat_max_s have passed since the
  // last fused one; it is a still camera instead: zero velocity and angular rate, to cone_repeat_sigma_v_m_s and
  // cone_repeat_sigma_omega_rad_s per axis (keep them above the motion that moves a cone's points cone_repeat_px in
  // a frame period: cone_repeat_px * depth * frame rate / fx, and cone_repeat_px * frame rate / fx). 0 = every
  // frame is fused.
  double cone_repeat_px = 0.0;
  double cone_repeat_max_s = 1.0;
  double cone_repeat_sigma_v_m_s = 0.01;
  double cone_repeat_sigma_omega_rad_s = 0.002;

  // Options beyond the thesis.
  QuatIntegration quat_integration = QuatIntegration::kFirstOrder;
  bool estimate_gyro_bias = false;  // three more states: z_gyro = omega + b (3.2.1)
  bool joseph_update = false;       // (I-KH) P (I-KH)' + K R K' instead of (I-KH) P

  // Initial standard deviations of the states not measured by the camera.
  double init_sigma_omega_rad_s = 1.0;
  double init_sigma_v_m_s = 0.5;
  double init_sigma_a_m_s2 = 2.0;
  double init_sigma_gyro_bias_rad_s = 0.02;

  // IMU-only (orientation-only) operation: initialise from the first
  // accelerometer sample near g (tilt; heading 0) instead of waiting for a camera
  // pose. Use with accel_mode = kOrientation, as no position is observed.
  bool init_from_gravity = false;
  double init_sigma_tilt_rad = 0.05;
  double init_sigma_heading_rad =
      0.1;  // arbitrary heading, but a 4D quaternion covariance must stay small to stay linear
  double init_sigma_p_m = 1.0;

  // Measurement buffer (section 6.3).
  double max_delay_s = 0.2;          // camera frames up to this late are applied at their stamp
  double time_jump_reset_s = 0.5;    // an IMU stamp this far behind the last one is a time jump: reset
  double max_predict_step_s = 0.02;  // longer gaps are predicted in sub-steps (first-order (2.70) needs small dt)

  // The lever arm (beyond the thesis, whose (3.26) takes the origins as
  // coincident): the IMU at r = ImuMeasurement::p_imu_in_camera_m (from the
  // camera-IMU tf) feels ω×(ω×r) + α×r on top of (5.39). ω×(ω×r) is modelled
  // (with its Jacobian). α is not in the state: with alpha_from_gyro it is the
  // change of the estimated ω between the last two gyro updates (an input, its
  // error sigma_angular_accel_rad_s2 per axis as measurement noise on α×r);
  // without it α×r is all noise (handheld turns reach ~10 rad/s²).
  bool model_lever_arm = true;
  bool alpha_from_gyro = true;
  double sigma_angular_accel_rad_s2 = 2.0;

  // Accelerometer bias b_a (camera axes): three more states, z_acc = h + b_a.
  bool estimate_accel_bias = false;
  double sigma_accel_bias_m_s2_per_sqrt_s = 1e-3;  // bias random walk
  double init_sigma_accel_bias_m_s2 = 0.1;

  // Motion model in camera outages (beyond (5.19)): v and a decay as
  // exp(-dt/τ); 0 keeps the thesis's undamped constant-acceleration model.
  double velocity_time_constant_s = 0.0;
  double accel_time_constant_s = 0.0;

  // Returns an empty string when valid, otherwise a message naming the member.
  std::string Validate() const;
};

}  // namespace pose_ekf
