// The survey's IMU side: the accelerometer's specific force carried into the levelled world frame by
// the gyro (the linear start's velocity changes).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "../src/imu_track.h"

namespace cone_survey {
namespace {

// The rig turns about the world's vertical at a constant rate (the IMU 90 deg about x from the camera)
// while it accelerates at a_world: the IMU measures R(t)^T (a_world + g z) in its own frame, and
// integrated back into the world frame that is (a_world + g z) over every interval.
TEST(ImuTrack, SpecificForceIntegralTurnsWithTheGyro) {
  const double rate_rad_s = 1.3, g = 9.80665, dt = 0.01;
  const Eigen::Vector3d a_world(0.8, -0.3, 0.2);
  const Eigen::Matrix3d R_camera_imu = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  // The camera's rotation at t = 0 in the world: looking along +x, levelled (camera z forward, y down).
  Eigen::Matrix3d R_world_camera0;
  R_world_camera0 << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const Eigen::Vector3d omega_world = rate_rad_s * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d omega_imu = (R_world_camera0 * R_camera_imu).transpose() * omega_world;  // constant: about z
  std::vector<ImuReading> imu;
  for (int i = 0; i < 300; ++i) {
    ImuReading r;
    r.stamp_s = (i + 0.5) * dt;  // the middle of the interval it covers
    const Eigen::Matrix3d R_world_imu =
        Eigen::AngleAxisd(rate_rad_s * r.stamp_s, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R_world_camera0 *
        R_camera_imu;
    r.gyro_rad_s = omega_imu;
    r.accel_m_s2 = R_world_imu.transpose() * (a_world + g * Eigen::Vector3d::UnitZ());
    imu.push_back(r);
  }
  const GyroIntegrator gyro(imu, R_camera_imu);
  for (const double t_ref : {0.5, 1.0, 1.7}) {
    const Eigen::Matrix3d R_ref =
        Eigen::AngleAxisd(rate_rad_s * t_ref, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R_world_camera0;
    const double t_a = t_ref - 0.05, t_b = t_ref + 0.06;
    const Eigen::Vector3d got = gyro.SpecificForceIntegral(t_a, t_b, t_ref, R_ref, Eigen::Vector3d::Zero());
    const Eigen::Vector3d want = (a_world + g * Eigen::Vector3d::UnitZ()) * (t_b - t_a);
    EXPECT_LT((got - want).norm(), 2e-3 * want.norm()) << "t_ref " << t_ref << ": " << got.transpose();
  }
  // A gyro bias taken off that is not there tilts the frame away from the truth as time passes from t_ref.
  const Eigen::Matrix3d R_ref =
      Eigen::AngleAxisd(rate_rad_s, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R_world_camera0;
  const Eigen::Vector3d biased = gyro.SpecificForceIntegral(1.0, 2.0, 1.0, R_ref, Eigen::Vector3d(0.2, 0.0, 0.0));
  EXPECT_GT((biased - (a_world + g * Eigen::Vector3d::UnitZ())).norm(), 0.5);
}

}  // namespace
}  // namespace cone_survey
