// Unit tests of the filter core: initialisation, each update, the mirrored
// quaternion, gates, non-finite input, covariance symmetry/PSD, options.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "pose_ekf/core/ekf_core.h"
#include "pose_ekf/testing/synthetic_rig.h"
#include "pose_math/covariance.h"
#include "pose_math/rotation.h"

namespace pose_ekf {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using pose_ekf_test::Camera;
using pose_ekf_test::SomePose;

double MinEigenvalue(const StateMatrix& P) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(P)).eigenvalues().minCoeff();
}

TEST(EkfCore, InitializesFromFirstCameraPose) {
  EkfCore ekf{EkfConfig{}};
  EXPECT_FALSE(ekf.initialized());
  const CameraMeasurement m = Camera(1.0, SomePose());
  ASSERT_TRUE(ekf.Initialize(m));
  EXPECT_EQ(ekf.state().x.size(), kBaseStates);
  EXPECT_LT((ekf.Pose().pose.q - m.T_cones_camera.q).norm(), 1e-15);
  EXPECT_LT((ekf.Pose().pose.t - m.T_cones_camera.t).norm(), 1e-15);
  EXPECT_LT((ekf.Pose().cov - m.cov).norm(), 1e-15);
  EXPECT_DOUBLE_EQ(ekf.state().stamp_s, 1.0);
}

TEST(EkfCore, RefusesNonFiniteInitialPose) {
  EkfCore ekf{EkfConfig{}};
  CameraMeasurement m = Camera(1.0, SomePose());
  m.T_cones_camera.t.x() = kNaN;
  EXPECT_FALSE(ekf.Initialize(m));
  EXPECT_FALSE(ekf.initialized());
}

TEST(EkfCore, CameraUpdatePullsTowardsMeasurementAndShrinksCovariance) {
  EkfCore ekf{EkfConfig{}};
  ASSERT_TRUE(ekf.Initialize(Camera(0.0, SomePose())));
  ekf.Predict(0.1);
  const double var_before = ekf.state().P(kP, kP);
  pose_math::Pose moved = SomePose();
  moved.t.x() += 0.02;
  ASSERT_EQ(ekf.UpdateCamera(Camera(0.1, moved)), UpdateResult::kApplied);
  const double x = ekf.Pose().pose.t.x();
  EXPECT_GT(x, SomePose().t.x() + 0.005);
  EXPECT_LT(x, moved.t.x());
  EXPECT_LT(ekf.state().P(kP, kP), var_before);
  EXPECT_NEAR(ekf.state().x.segment<4>(kQ).norm(), 1.0, 1e-15);  // (5.41)
}

TEST(EkfCore, MirroredQuaternionGivesTheSameUpdate) {
  EkfCore a{EkfConfig{}}, b{EkfConfig{}};
  ASSERT_TRUE(a.Initialize(Camera(0.0, SomePose())));
  ASSERT_TRUE(b.Initialize(Camera(0.0, SomePose())));
  a.Predict(0.05);
  b.Predict(0.05);
  pose_math::Pose z = SomePose();
  z.q = pose_math::Multiply(pose_math::QuatFromRotationVector(Eigen::Vector3d(0.01, 0, 0)), z.q);
  CameraMeasurement m = Camera(0.05, z), mirrored = m;
  mirrored.T_cones_camera.q = -m.T_cones_camera.q;
  ASSERT_EQ(a.UpdateCamera(m), UpdateResult::kApplied);
  ASSERT_EQ(b.UpdateCamera(mirrored), UpdateResult::kApplied);
  EXPECT_LT((a.state().x - b.state().x).norm(), 1e-12);
  EXPECT_GT(a.state().x.segment<4>(kQ).dot(SomePose().q), 0.99);  // not averaged towards the antipode
}

TEST(EkfCore, GyroUpdateMeasuresAngularVelocity) {
  EkfCore ekf{EkfConfig{}};
  ASSERT_TRUE(ekf.Initialize(Camera(0.0, SomePose())));
  ImuMeasurement m;
  m.omega_camera_rad_s << 0.5, -0.2, 0.1;
  m.has_accel = false;
  for (int i = 1; i <= 20; ++i) {
    ekf.Predict(0.01 * i);
    ASSERT_EQ(ekf.UpdateGyro(m), UpdateResult::kApplied);
  }
  EXPECT_LT((ekf.omega_camera_rad_s() - m.omega_camera_rad_s).norm(), 0.01);
}

TEST(EkfCore, AccelerometerGateRejectsFarFromGravity) {
  EkfConfig c;
  c.accel_mode = AccelMode::kOrientation;
  EkfCore ekf{c};
  ASSERT_TRUE(ekf.Initialize(Camera(0.0, SomePose())));
  ImuMeasurement m;
  m.accel_camera_m_s2 = Eigen::Vector3d(0, 0, c.gravity_m_s2 + 2.0 * c.accel_gate_m_s2);
  const FilterState before = ekf.state();
  EXPECT_EQ(ekf.UpdateAccel(m), UpdateResult::kGated);  // (5.34)
  EXPECT_EQ((ekf.state().x - before.x).norm(), 0.0);
  c.accel_gate_m_s2 = 0.0;  // gate disabled
  ekf.SetConfig(c);
  EXPECT_EQ(ekf.UpdateAccel(m), UpdateResult::kApplied);
}

// With a tilted initial estimate, gravity alone corrects roll and pitch ((5.36) (5.37)).
TEST(EkfCore, AccelerometerCorrectsTiltButNotHeading) {
  EkfConfig c;
  c.accel_mode = AccelMode::kOrientation;
  c.use_gyro = true;
  EkfCore ekf{c};
  pose_math::Pose truth = SomePose();
  pose_math::Pose tilted = truth;
  tilted.q = pose_math::Multiply(pose_math::QuatFromRotationVector(Eigen::Vector3d(0.05, -0.04, 0.0)), truth.q);
  ASSERT_TRUE(ekf.Initialize(Camera(0.0, tilted, 0.1, 0.1)));
  ImuMeasurement m;
  m.accel_camera_m_s2 = pose_math::RotationFromQuat(truth.q).transpose() * Eigen::Vector3d(0, 0, c.gravity_m_s2);
  for (int i = 1; i <= 300; ++i) {
    ekf.Predict(0.01 * i);
    ASSERT_EQ(ekf.UpdateGyro(m), UpdateResult::kApplied);
    ASSERT_EQ(ekf.UpdateAccel(m), UpdateResult::kApplied);
  }
  const Eigen::Matrix3d R_est = pose_math::RotationFromQuat(ekf.Pose().pose.q);
  const Eigen::Matrix3d R_true = pose_math::RotationFromQuat(truth.q);
  // The camera's "up" agrees with the truth: tilt corrected.
  EXPECT_LT((R_est.transpose().col(2) - R_true.transpose().col(2)).norm(), 2e-3);
}

TEST(EkfCore, NonFiniteMeasurementsAreRejectedWithoutTouchingTheState) {
  EkfCore ekf{EkfConfig{}};
  ASSERT_TRUE(ekf.Initialize(Camera(0.0, SomePose())));
  ekf.Predict(0.01);
  const FilterState before = ekf.state();
  CameraMeasurement cam = Camera(0.01, SomePose());
  cam.cov(5, 5) = kNaN;
  EXPECT_EQ(ekf.UpdateCamera(cam), UpdateResult::kRejectedNonFinite);
  ImuMeasurement imu;
  imu.omega_camera_rad_s.y() = std::numeric_limits<double>::infinity();
  imu.accel_camera_m_s2.z() = kNaN;
  EXPECT_EQ(ekf.UpdateGyro(imu), UpdateResult::kRejectedNonFinite);
  EXPECT_EQ(ekf.UpdateAccel(imu), UpdateResult::kRejectedNonFinite);
  EXPECT_EQ((ekf.state().x - before.x).norm(), 0.0);
  EXPECT_EQ((ekf.state().P - before.P).norm(), 0.0);
}

TEST(EkfCore, SwitchedOffUpdatesDoNothing) {
  EkfConfig c;
  c.use_camera = false;
  c.use_gyro = false;
  c.accel_mode = AccelMode::kOff;
  EkfCore ekf{c};
  ASSERT_TRUE(ekf.Initialize(Camera(0.0, SomePose())));
  EXPECT_EQ(ekf.UpdateCamera(Camera(0.0, SomePose())), UpdateResult::kDisabled);
  EXPECT_EQ(ekf.UpdateGyro(ImuMeasurement{}), UpdateResult::kDisabled);
  EXPECT_EQ(ekf.UpdateAccel(ImuMeasurement{}), UpdateResult::kDisabled);
}

class CovarianceTest : public ::testing::TestWithParam<bool> {};

// Many updates of every kind: P stays symmetric and positive semi-definite.
TEST_P(CovarianceTest, StaysSymmetricPsd) {
  EkfConfig c;
  c.joseph_update = GetParam();
  c.estimate_gyro_bias = true;
  c.camera_gate_chi2 = 0.0;  // random poses, several sigma off: fused all the same
  EkfCore ekf{c};
  ASSERT_TRUE(ekf.Initialize(Camera(0.0, SomePose())));
  srand(3);
  for (int i = 1; i <= 500; ++i) {
    ekf.Predict(0.01 * i);
    ImuMeasurement m;
    m.omega_camera_rad_s = Eigen::Vector3d::Random();
    m.accel_camera_m_s2 = pose_math::RotationFromQuat(ekf.Pose().pose.q).transpose() * Eigen::Vector3d(0, 0, 9.8) +
                          0.1 * Eigen::Vector3d::Random();
    ekf.UpdateGyro(m);
    ekf.UpdateAccel(m);
    if (i % 3 == 0) {
      pose_math::Pose z = ekf.Pose().pose;
      z.t += 0.01 * Eigen::Vector3d::Random();
      ASSERT_EQ(ekf.UpdateCamera(Camera(0.01 * i, z, 0.002, 0.001)), UpdateResult::kApplied);
    }
    const StateMatrix& P = ekf.state().P;
    ASSERT_EQ((P - P.transpose()).norm(), 0.0) << i;
    ASSERT_GT(MinEigenvalue(P), -1e-12) << i;
  }
}

INSTANTIATE_TEST_SUITE_P(StandardAndJoseph, CovarianceTest, ::testing::Bool());

TEST(EkfCore, InitializesFromGravityForImuOnlyUse) {
  EkfConfig c;
  c.init_from_gravity = true;
  EkfCore ekf{c};
  const Eigen::Vector3d f_camera(1.0, -9.0, 3.0);
  EXPECT_FALSE(ekf.InitializeFromGravity(0.0, 2.0 * f_camera));  // |a| far from g: moving (5.34)
  const Eigen::Vector3d f = f_camera.normalized() * c.gravity_m_s2;
  ASSERT_TRUE(ekf.InitializeFromGravity(0.5, f));
  const Eigen::Matrix3d R = pose_math::RotationFromQuat(ekf.Pose().pose.q);
  EXPECT_LT((R * f.normalized() - Eigen::Vector3d::UnitZ()).norm(), 1e-12);  // specific force points up
  EXPECT_DOUBLE_EQ(ekf.state().stamp_s, 0.5);
  EXPECT_GT(MinEigenvalue(ekf.state().P.bottomRightCorner(9, 9)), 0.0);
}

TEST(EkfConfig, InvalidValuesAreNamed) {
  EkfConfig c;
  c.sigma_gyro_rad_s = -1.0;
  c.max_delay_s = std::numeric_limits<double>::quiet_NaN();
  const std::string err = c.Validate();
  EXPECT_NE(err.find("sigma_gyro_rad_s"), std::string::npos) << err;
  EXPECT_NE(err.find("max_delay_s"), std::string::npos) << err;
  EXPECT_THROW(EkfCore{c}, std::invalid_argument);
  EXPECT_EQ(EkfConfig{}.Validate(), "");
}

}  // namespace
}  // namespace pose_ekf
