// Measurements as the core sees them: thesis quantities, no ROS types.
#pragma once

#include <Eigen/Core>

#include "pose_math/pose.h"

namespace pose_ekf {

// The camera pose in the cones frame, T_cones_camera (M_C H), at exposure time,
// with its constrained 7x7 covariance over (q0 qx qy qz px py pz) (5.24), section 5.6.4.
struct CameraMeasurement {
  double stamp_s = 0.0;
  pose_math::Pose T_cones_camera;
  pose_math::Matrix7d cov = pose_math::Matrix7d::Zero();
};

// A camera pose the filter can use: finite pose and covariance, and a quaternion
// that can be normalised. Checked by the buffer and again by EkfCore, which may
// be driven directly.
inline bool PoseUsable(const CameraMeasurement& m) {
  return m.T_cones_camera.q.allFinite() && m.T_cones_camera.t.allFinite() && m.cov.allFinite() &&
         m.T_cones_camera.q.norm() > 1e-6;
}

// One IMU sample already rotated into the camera frame {C} (the camera-IMU
// rotation of 3.2.2 is applied by the adapter). Accelerometer: specific force,
// +g upwards at rest (REP-145), which is the thesis's C z_acl (5.30).
struct ImuMeasurement {
  double stamp_s = 0.0;
  bool has_gyro = true;
  bool has_accel = true;
  Eigen::Vector3d omega_camera_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_camera_m_s2 = Eigen::Vector3d::Zero();
  // The IMU's origin in the camera frame (the lever arm, from the tf camera_optical -> imu).
  Eigen::Vector3d p_imu_in_camera_m = Eigen::Vector3d::Zero();
  // Optional per-sample covariances (used when EkfConfig::use_message_imu_covariance).
  bool has_covariance = false;
  Eigen::Matrix3d gyro_cov = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d accel_cov = Eigen::Matrix3d::Zero();
};

}  // namespace pose_ekf
