#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "imu_driver/core/calibration_session.h"
#include "imu_driver/core/camera_imu_rotation.h"
#include "imu_driver/core/gyro_bias.h"
#include "pose_math/rotation.h"

namespace imu_driver {
namespace {

double AngleDeg(const Eigen::Matrix3d& A, const Eigen::Matrix3d& B) {
  return pose_math::AngleAxisFromRotation(A.transpose() * B).angle_rad * 180.0 / M_PI;
}

Eigen::Matrix3d RandomRotation(std::mt19937& rng, double max_angle_rad) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, max_angle_rad);
  return pose_math::RotationFromAngleAxis({u(rng), Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized()});
}

TEST(GyroBias, RecoversBiasWithinThreeStandardErrors) {
  std::mt19937 rng(4);
  const Eigen::Vector3d bias(0.012, -0.007, 0.003);
  const Eigen::Vector3d sigma(0.004, 0.006, 0.005);
  std::normal_distribution<double> n(0.0, 1.0);
  GyroBiasEstimator est;
  const int per_pose = 3000;
  for (int pose = 0; pose < 4; ++pose) {
    const Eigen::Matrix3d R_imu_world = RandomRotation(rng, M_PI);
    est.NewOrientation();
    for (int k = 0; k < per_pose; ++k) {
      const Eigen::Vector3d w = bias + sigma.cwiseProduct(Eigen::Vector3d(n(rng), n(rng), n(rng)));
      const Eigen::Vector3d a = R_imu_world * Eigen::Vector3d(0, 0, 9.81) + 0.05 * Eigen::Vector3d(n(rng), n(rng), 0);
      est.Add(w, a);
    }
  }
  const GyroBiasResult r = est.Compute();
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.orientations.size(), 4u);
  EXPECT_EQ(r.samples, 4u * per_pose);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(std::abs(r.bias_rad_s(i) - bias(i)), 3.0 * sigma(i) / std::sqrt(4.0 * per_pose)) << i;
    EXPECT_NEAR(r.sigma_rad_s(i), sigma(i), 0.05 * sigma(i)) << i;
  }
}

TEST(GyroBias, SplitsOrientationsByGravityAndRefusesMotion) {
  GyroBiasEstimator est;
  for (int k = 0; k < 200; ++k) est.Add(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 9.81));
  for (int k = 0; k < 200; ++k) est.Add(Eigen::Vector3d::Zero(), Eigen::Vector3d(9.81, 0, 0));
  GyroBiasResult r = est.Compute();
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.orientations.size(), 2u);

  GyroBiasEstimator moving;
  for (int k = 0; k < 200; ++k) moving.Add(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, (k % 2) ? 1.0 : -1.0, 9.81));
  r = moving.Compute();
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("moved"), std::string::npos);

  GyroBiasEstimator empty;
  EXPECT_FALSE(empty.Compute().ok);
  empty.Add(Eigen::Vector3d(NAN, 0, 0), Eigen::Vector3d(0, 0, 9.81));  // ignored
  EXPECT_EQ(empty.samples(), 0u);
}

TEST(GyroBias, ConstantRotationAboutGravityIsRefused) {
  GyroBiasEstimator est;
  for (int k = 0; k < 500; ++k) est.Add(Eigen::Vector3d(0, 0, 0.3), Eigen::Vector3d(0, 0, 9.81));
  const GyroBiasResult r = est.Compute();
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("turning"), std::string::npos);
}

TEST(CalibrationSession, CollectsForTheSpanThenReplacesBiasAndSigma) {
  CalibrationSession session({Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(0.5, 0.5, 0.5), false});
  std::string msg;
  ImuSample s;
  s.si.accel_imu_m_s2 = {0.0, 0.0, 9.81};
  EXPECT_FALSE(session.Add(s).has_value());  // not running: ignored
  ASSERT_TRUE(session.Start(1.0, &msg));
  EXPECT_FALSE(session.Start(1.0, &msg));  // one at a time
  EXPECT_NE(msg.find("already"), std::string::npos);
  std::optional<GyroBiasResult> result;
  for (int k = 0; k <= 100 && !result; ++k) {
    s.stamp_s = 10.0 + 0.01 * k;
    s.si.omega_imu_rad_s = {0.02 + ((k % 2) ? 0.001 : -0.001), -0.01, 0.005};
    result = session.Add(s);
  }
  ASSERT_TRUE(result.has_value());
  ASSERT_TRUE(result->ok) << result->message;
  const GyroCalibration c = session.current();
  EXPECT_TRUE(c.calibrated);
  EXPECT_NEAR(c.bias_rad_s(0), 0.02, 1e-4);
  EXPECT_NEAR(c.bias_rad_s(1), -0.01, 1e-12);
  EXPECT_NEAR(c.sigma_rad_s(0), 0.001, 1e-4);
  EXPECT_FALSE(session.running());
}

// Gravity pairs from a known rotation, with accelerometer and extrinsic noise.
std::vector<GravityPair> MakePairs(std::mt19937& rng, const Eigen::Matrix3d& R_camera_imu, int poses,
                                   double accel_noise_m_s2, double extrinsic_noise_deg) {
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Vector3d up_in_grid(0, 0, -1);
  std::vector<GravityPair> pairs;
  for (int i = 0; i < poses; ++i) {
    const Eigen::Matrix3d R_camera_grid = RandomRotation(rng, 0.8) * pose_math::RotX(M_PI);
    const Eigen::Vector3d up_camera = R_camera_grid * up_in_grid;
    const Eigen::Vector3d accel_imu =
        9.81 * R_camera_imu.transpose() * up_camera + accel_noise_m_s2 * Eigen::Vector3d(n(rng), n(rng), n(rng));
    const Eigen::Matrix3d measured = RandomRotation(rng, extrinsic_noise_deg * M_PI / 180.0) * R_camera_grid;
    pairs.push_back(MakeGravityPair(accel_imu, measured, up_in_grid));
  }
  return pairs;
}

TEST(CameraImuRotation, SvdAndEulerRecoverKnownRotationWithinTwoTenthsDegree) {
  std::mt19937 rng(8);
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Matrix3d R_true = RandomRotation(rng, 0.6);
    const auto pairs = MakePairs(rng, R_true, 12, 0.005, 0.03);
    const RotationFit svd = FitRotationSvd(pairs);
    const RotationFit euler = FitRotationEuler(pairs);
    ASSERT_TRUE(svd.ok) << svd.message;
    ASSERT_TRUE(euler.ok) << euler.message;
    EXPECT_LT(AngleDeg(svd.R_camera_imu, R_true), 0.2) << trial;
    EXPECT_LT(AngleDeg(euler.R_camera_imu, R_true), 0.2) << trial;
    EXPECT_LT(AngleDeg(svd.R_camera_imu, euler.R_camera_imu), 0.02) << trial;  // same minimum
    EXPECT_NEAR(svd.R_camera_imu.determinant(), 1.0, 1e-9);
    EXPECT_LT(svd.rms_residual_deg, 0.2);
  }
}

TEST(CameraImuRotation, NoiseFreeIsExactAndLinearLeastSquaresMatches) {
  std::mt19937 rng(9);
  const Eigen::Matrix3d R_true = RandomRotation(rng, M_PI);  // any rotation, no initial guess needed for SVD
  const auto pairs = MakePairs(rng, R_true, 6, 0.0, 0.0);
  EXPECT_LT(AngleDeg(FitRotationSvd(pairs).R_camera_imu, R_true), 1e-6);
  EXPECT_LT((FitLinearLeastSquares(pairs) - R_true).norm(), 1e-9);
  EXPECT_LT(AngleDeg(FitRotationEuler(pairs, FitRotationSvd(pairs).R_camera_imu).R_camera_imu, R_true), 1e-6);
}

TEST(CameraImuRotation, DegenerateInputIsRefusedWithAReason) {
  std::vector<GravityPair> one = {{Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ()}};
  EXPECT_FALSE(FitRotationSvd(one).ok);
  std::vector<GravityPair> parallel = {{Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX()},
                                       {2 * Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX()}};
  const RotationFit f = FitRotationSvd(parallel);
  EXPECT_FALSE(f.ok);
  EXPECT_NE(f.message.find("parallel"), std::string::npos);
  std::vector<GravityPair> nan = {{Eigen::Vector3d(NAN, 0, 1), Eigen::Vector3d::UnitX()},
                                  {Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitY()}};
  EXPECT_FALSE(FitRotationEuler(nan).ok);
}

}  // namespace
}  // namespace imu_driver
