// The survey's internals: rotations from the gyro, the accelerometer's up direction, and the
// frame-to-frame cone tracks. ROS-free.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cone_survey/survey.h"

namespace cone_survey {

Eigen::Matrix3d ExpSo3(const Eigen::Vector3d& w);

// Integrates the gyro (2.71) over any interval, in the camera frame.
class GyroIntegrator {
 public:
  GyroIntegrator(const std::vector<ImuReading>& imu, const Eigen::Matrix3d& R_camera_imu);
  double period_s() const { return period_s_; }
  // R_a^T R_b: the camera's rotation from t_a to t_b (camera_optical at t_b in camera_optical at t_a),
  // with bias_imu (rad/s, IMU frame) taken off every sample.
  Eigen::Matrix3d Delta(double t_a_s, double t_b_s, const Eigen::Vector3d& bias_imu) const;
  // The accelerometer's mean specific force over [t - half, t + half] in the camera frame, normalised:
  // up, while the rig does not accelerate. False when no sample lies there.
  bool UpInCamera(double t_s, double half_window_s, Eigen::Vector3d* up) const;
  // The accelerometer's specific force over [t_a, t_b], integrated in the levelled world frame whose
  // camera rotation at t_ref is R_world_camera_ref (the gyro carries it to each sample): the velocity
  // change over the interval plus g (t_b - t_a) z, m/s. The lever arm is neglected.
  Eigen::Vector3d SpecificForceIntegral(double t_a_s, double t_b_s, double t_ref_s,
                                        const Eigen::Matrix3d& R_world_camera_ref,
                                        const Eigen::Vector3d& bias_imu) const;
  // The mean gyro over the first `still_s` seconds when the rig was still then (spread below
  // 0.02 rad/s per axis, accelerometer within 0.3 m/s^2 of g); false otherwise.
  bool StillStartBias(double still_s, Eigen::Vector3d* bias_imu) const;

 private:
  const std::vector<ImuReading>& imu_;
  Eigen::Matrix3d R_camera_imu_;
  double period_s_ = 0.01;
};

// A cone followed from frame to frame: (frame index, sighting index) in frame order.
struct Track {
  std::vector<std::pair<int, int>> sightings;
};

// Each sighting joins the track whose last sighting, carried to this frame by the gyro's rotation
// (a rotation-only homography K R^T K^-1), lands nearest within the gate; else it starts a track.
std::vector<Track> TrackCones(const SurveyInput& input, const GyroIntegrator& gyro, const Eigen::Vector3d& bias_imu,
                              const SurveyConfig& config);

}  // namespace cone_survey
