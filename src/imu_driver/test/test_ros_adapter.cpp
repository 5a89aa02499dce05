#include <gtest/gtest.h>

#include <cmath>

#include "imu_driver/node/ros_adapter.h"

namespace imu_driver {
namespace {

ImuSample Sample() {
  ImuSample s;
  s.si.omega_imu_rad_s = {0.1, -0.2, 0.3};
  s.si.accel_imu_m_s2 = {0.5, 0.0, 9.8};
  s.stamp_s = 1234.5;
  return s;
}

TEST(FillImuMessage, Rep145InImuFrame) {
  DriverConfig c;
  c.accel_noise_sigma_m_s2 = Eigen::Vector3d(0.1, 0.2, 0.3);
  sensor_msgs::Imu m;
  FillImuMessage(Sample(), c, {Eigen::Vector3d(0.01, 0.01, 0.01), Eigen::Vector3d(0.01, 0.02, 0.03), true}, &m);
  EXPECT_EQ(m.header.frame_id, "imu");
  EXPECT_NEAR(m.header.stamp.toSec(), 1234.495, 1e-6);  // the midpoint of the 10 ms interval (REP-145)
  c.stamp_at_interval_midpoint = false;
  FillImuMessage(Sample(), c, {Eigen::Vector3d(0.01, 0.01, 0.01), Eigen::Vector3d(0.01, 0.02, 0.03), true}, &m);
  EXPECT_NEAR(m.header.stamp.toSec(), 1234.5, 1e-6);
  c.stamp_at_interval_midpoint = true;
  ImuSample at_zero = Sample();
  at_zero.stamp_s = 0.001;  // read before sim time started: the shift must not make it negative
  FillImuMessage(at_zero, c, {Eigen::Vector3d(0.01, 0.01, 0.01), Eigen::Vector3d(0.01, 0.02, 0.03), true}, &m);
  EXPECT_EQ(m.header.stamp.toSec(), 0.0);
  EXPECT_EQ(m.orientation_covariance[0], -1.0);
  EXPECT_NEAR(m.angular_velocity.x, 0.09, 1e-12);  // bias removed
  EXPECT_NEAR(m.angular_velocity.y, -0.21, 1e-12);
  EXPECT_NEAR(m.linear_acceleration.z, 9.8, 1e-12);
  EXPECT_NEAR(m.angular_velocity_covariance[0], 1e-4, 1e-15);
  EXPECT_NEAR(m.angular_velocity_covariance[8], 9e-4, 1e-15);
  EXPECT_EQ(m.angular_velocity_covariance[1], 0.0);
  EXPECT_NEAR(m.linear_acceleration_covariance[4], 0.04, 1e-15);
}

TEST(FillImuMessage, CameraFrameRotatesVectorsAndCovariance) {
  DriverConfig c;
  c.subtract_gyro_bias = false;
  c.publish_in_camera_frame = true;
  // R_camera_imu: 90 deg about z, so x_imu -> y_camera and y_imu -> -x_camera.
  c.q_camera_imu = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  sensor_msgs::Imu m;
  FillImuMessage(Sample(), c, {Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(0.01, 0.02, 0.03), true}, &m);
  EXPECT_EQ(m.header.frame_id, "camera_optical");
  EXPECT_NEAR(m.angular_velocity.x, 0.2, 1e-12);  // (3.26): ω_C = R ω_I
  EXPECT_NEAR(m.angular_velocity.y, 0.1, 1e-12);
  EXPECT_NEAR(m.angular_velocity.z, 0.3, 1e-12);
  EXPECT_NEAR(m.linear_acceleration.y, 0.5, 1e-12);
  EXPECT_NEAR(m.angular_velocity_covariance[0], 4e-4, 1e-15);  // σ_y² now on x
  EXPECT_NEAR(m.angular_velocity_covariance[4], 1e-4, 1e-15);
}

TEST(GyroCalibrationYaml, HasTheParameterNames) {
  GyroBiasResult r;
  r.ok = true;
  r.bias_rad_s = Eigen::Vector3d(0.001, -0.002, 0.003);
  r.sigma_rad_s = Eigen::Vector3d(0.01, 0.02, 0.03);
  const std::string y = GyroCalibrationYaml(r);
  EXPECT_NE(y.find("gyro_bias_rad_s: [0.001, -0.002, 0.003]"), std::string::npos) << y;
  EXPECT_NE(y.find("gyro_noise_sigma_rad_s: [0.01, 0.02, 0.03]"), std::string::npos) << y;
}

}  // namespace
}  // namespace imu_driver
