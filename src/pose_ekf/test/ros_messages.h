// Synthetic-rig measurements as the nodelet's input messages (shared by the
// adapter and replay tests).
#pragma once

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <sensor_msgs/Imu.h>

#include <Eigen/Geometry>

#include "pose_ekf/core/measurement.h"
#include "pose_math/covariance.h"
#include "rig_model/ros/conversions.h"

namespace pose_ekf_test {

// The IMU is mounted rotated against the camera (3.2.2); tf would give this.
inline const Eigen::Quaterniond kQCameraImu(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()) *
                                            Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()));

inline geometry_msgs::PoseWithCovarianceStamped CameraMsg(const pose_ekf::CameraMeasurement& m) {
  ros::Time stamp;
  stamp.fromSec(m.stamp_s);
  return rig_model::ToPoseWithCovarianceStamped({m.T_cones_camera, m.cov}, stamp, "cones");
}

inline sensor_msgs::Imu ImuMsg(const pose_ekf::ImuMeasurement& m) {
  sensor_msgs::Imu msg;
  msg.header.stamp.fromSec(m.stamp_s);
  msg.header.frame_id = "imu";
  msg.orientation_covariance[0] = -1.0;  // REP-145: no orientation
  const Eigen::Matrix3d R_imu_camera = kQCameraImu.toRotationMatrix().transpose();
  const Eigen::Vector3d w = R_imu_camera * m.omega_camera_rad_s, a = R_imu_camera * m.accel_camera_m_s2;
  msg.angular_velocity.x = w.x();
  msg.angular_velocity.y = w.y();
  msg.angular_velocity.z = w.z();
  msg.linear_acceleration.x = a.x();
  msg.linear_acceleration.y = a.y();
  msg.linear_acceleration.z = a.z();
  return msg;
}

}  // namespace pose_ekf_test
