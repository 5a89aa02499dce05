// Synthetic-rig measurements as the nodelet's input messages (shared by the
// adapter and replay tests).
#pragma once

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <sensor_msgs/Imu.h>

#include <Eigen/Geometry>

#include "pose_ekf/core/measurement.h"
#include "pose_math/covariance.h"

namespace pose_ekf_test {

// The IMU is mounted rotated against the camera (3.2.2); tf would give this.
inline const Eigen::Quaterniond kQCameraImu(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()) *
                                            Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()));

inline geometry_msgs::PoseWithCovarianceStamped CameraMsg(const pose_ekf::CameraMeasurement& m) {
  geometry_msgs::PoseWithCovarianceStamped msg;
  msg.header.stamp.fromSec(m.stamp_s);
  msg.header.frame_id = "cones";
  const auto& T = m.T_cones_camera;
  msg.pose.pose.position.x = T.t.x();
  msg.pose.pose.position.y = T.t.y();
  msg.pose.pose.position.z = T.t.z();
  msg.pose.pose.orientation.w = T.q[0];
  msg.pose.pose.orientation.x = T.q[1];
  msg.pose.pose.orientation.y = T.q[2];
  msg.pose.pose.orientation.z = T.q[3];
  const pose_math::Matrix6d cov6 = pose_math::CovarianceRosFromThesis(T.q, m.cov);
  Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(msg.pose.covariance.data()) = cov6;
  return msg;
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
