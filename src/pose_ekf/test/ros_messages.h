// Synthetic-rig measurements as the nodelet's input messages (shared by the
// adapter and replay tests).
#pragma once

#include <cone_tracker/ConeObservations.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <sensor_msgs/Imu.h>

#include <Eigen/Geometry>

#include "pose_ekf/core/cone_measurement.h"
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

inline cone_tracker::ConeObservations ObservationsMsg(const pose_ekf::ConeFrame& f) {
  cone_tracker::ConeObservations msg;
  msg.header.stamp.fromSec(f.stamp_s);
  msg.header.frame_id = "camera_optical";
  msg.fx = f.K.fx_px, msg.fy = f.K.fy_px, msg.cx = f.K.cx_px, msg.cy = f.K.cy_px;
  for (const pose_ekf::ConeObservation& o : f.cones) {
    cone_tracker::ConeObservation c;
    c.cone_id = o.cone_id;
    boost::array<double, 2>* px[3] = {&c.peak_px, &c.mid_px, &c.base_px};
    boost::array<double, 4>* cov[3] = {&c.peak_cov_px2, &c.mid_cov_px2, &c.base_cov_px2};
    for (int k = 0; k < 3; ++k) {
      (*px[k])[0] = o.px[k].x(), (*px[k])[1] = o.px[k].y();
      for (int i = 0; i < 4; ++i) (*cov[k])[static_cast<size_t>(i)] = o.cov_px2[k](i / 2, i % 2);
    }
    msg.cones.push_back(c);
  }
  return msg;
}

}  // namespace pose_ekf_test
