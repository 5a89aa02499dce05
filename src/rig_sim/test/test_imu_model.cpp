#include <gtest/gtest.h>

#include <cmath>

#include <pose_math/quaternion.h>
#include <pose_math/rotation.h>

#include "rig_sim/imu_model.h"
#include "test_util.h"

namespace rig_sim {
namespace {
constexpr double kDegPerRad = 180.0 / 3.14159265358979323846;

double AngleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return pose_math::AngleAxisFromRotation(a.transpose() * b).angle_rad * kDegPerRad;
}

// Integrates the gyro with (2.71) over duration_s; returns the final error in degrees.
double GyroIntegrationErrorDeg(const ImuConfig& imu_cfg, const Trajectory& traj, double t0, double duration_s) {
  ImuSimulator imu(imu_cfg, traj);
  ImuSample s;
  do s = imu.Next();
  while (s.stamp_s < t0 - 1e-9);
  pose_math::Quat q = pose_math::QuatFromRotation(imu.R_cones_imu(s.stamp_s));
  const double dt = 1.0 / imu_cfg.rate_hz;
  while (s.stamp_s < t0 + duration_s - 1e-9) {
    s = imu.Next();
    q = pose_math::IntegrateExact(q, s.omega_imu_rad_s, dt);
  }
  return AngleDeg(pose_math::RotationFromQuat(q), imu.R_cones_imu(s.stamp_s));
}
}  // namespace

TEST(ImuModel, NoiseFreeGyroIntegratesToTheTrueOrientationOver10s) {
  const Scenario s = TestScenario("handheld", 5, 0, 0);
  const Trajectory traj(s.trajectory);
  ImuConfig cfg = s.imu;
  cfg.noise_enabled = false;
  cfg.quantize = false;
  // 10 s including the first shake (14-17 s), at up to ~200 deg/s.
  EXPECT_LT(GyroIntegrationErrorDeg(cfg, traj, 10.0, 10.0), 0.01);
  // With the Crista's 0.009 deg/s quantisation the error stays far below 0.01 deg too.
  cfg.quantize = true;
  EXPECT_LT(GyroIntegrationErrorDeg(cfg, traj, 10.0, 10.0), 0.01);
  // With the turn-on bias left in, the same check fails: it can detect an error.
  cfg.noise_enabled = true;
  cfg.gyro_bias_sigma_deg_s = 0.5;
  EXPECT_GT(GyroIntegrationErrorDeg(cfg, traj, 10.0, 10.0), 0.05);
}

TEST(ImuModel, AtRestTheAccelerometerReadsGravityInTheImuFrame) {
  const Scenario s = TestScenario("handheld", 5, 0, 0);
  const Trajectory traj(s.trajectory);
  ImuConfig cfg = s.imu;
  cfg.noise_enabled = false;
  cfg.quantize = false;
  ImuSimulator imu(cfg, traj);
  int checked = 0;
  for (int k = 0; k < 300; ++k) {
    const ImuSample smp = imu.Next();
    if (!traj.IsStill(smp.stamp_s - 0.01)) continue;
    const Eigen::Vector3d g_imu = imu.R_cones_imu(smp.stamp_s).transpose() * Eigen::Vector3d(0, 0, 9.81);
    EXPECT_LT((smp.accel_imu_m_s2 - g_imu).norm(), 1e-6);
    EXPECT_LT(smp.omega_imu_rad_s.norm(), 1e-9);
    ++checked;
  }
  EXPECT_GT(checked, 200);
  // The default mount: IMU z up when the camera looks horizontally, so at rest
  // gravity's reaction is mostly along +z of the IMU with a tilt from the pitch.
  const Eigen::Vector3d g_imu = imu.R_cones_imu(1.0).transpose() * Eigen::Vector3d::UnitZ();
  EXPECT_GT(g_imu.z(), 0.5);
}

TEST(ImuModel, NoisyQuantisedOutputAtRestAveragesToGravityPlusBias) {
  const Scenario s = TestScenario("still", 9, 0, 0);
  const Trajectory traj(s.trajectory);
  ImuSimulator imu(s.imu, traj);
  Eigen::Vector3d sum_acc = Eigen::Vector3d::Zero(), sum_gyro = Eigen::Vector3d::Zero(), bias = sum_gyro;
  const int n = 800;
  for (int k = 0; k < n; ++k) {
    const ImuSample smp = imu.Next();
    for (int i = 0; i < 3; ++i) {
      EXPECT_DOUBLE_EQ(smp.omega_imu_rad_s[i] * kDegPerRad, smp.gyro_raw[i] * 600.0 / 65536.0);
      EXPECT_DOUBLE_EQ(smp.accel_imu_m_s2[i], smp.accel_raw[i] * 196.1 / 65536.0);
    }
    sum_acc += smp.accel_imu_m_s2;
    sum_gyro += smp.omega_imu_rad_s;
    bias += smp.true_gyro_bias_rad_s;
  }
  EXPECT_NEAR((sum_acc / n).norm(), 9.81, 0.15);
  EXPECT_LT(((sum_gyro - bias) / n).norm() * kDegPerRad, 0.02);
  EXPECT_GT((bias / n).norm() * kDegPerRad, 0.01);  // a turn-on bias is there
}

TEST(ImuModel, RangeLimitsSaturate) {
  TrajectoryConfig tc;
  tc.duration_s = 5;
  tc.segments = {{SegmentKind::kShake, 0.5, 3.0, 0.4, 40.0, 4.0}};  // ~1000 deg/s
  const Trajectory traj(tc);
  ImuConfig cfg;
  cfg.noise_enabled = false;
  ImuSimulator imu(cfg, traj);
  bool saturated = false;
  double max_deg_s = 0;
  for (int k = 0; k < 300; ++k) {
    const ImuSample smp = imu.Next();
    saturated |= smp.saturated;
    max_deg_s = std::max(max_deg_s, smp.omega_imu_rad_s.cwiseAbs().maxCoeff() * kDegPerRad);
  }
  EXPECT_TRUE(saturated);
  EXPECT_LE(max_deg_s, 300.0);
  EXPECT_GT(max_deg_s, 299.0);
}

TEST(ImuModel, SameSeedSameSamples) {
  const Scenario s = TestScenario("shake", 4, 0, 0);
  const Trajectory traj(s.trajectory);
  ImuSimulator a(s.imu, traj), b(s.imu, traj);
  for (int k = 0; k < 50; ++k) {
    const ImuSample x = a.Next(), y = b.Next();
    ASSERT_EQ(x.omega_imu_rad_s, y.omega_imu_rad_s);
    ASSERT_EQ(x.accel_imu_m_s2, y.accel_imu_m_s2);
  }
}

}  // namespace rig_sim
