// Analytic Jacobians (5.22) (5.37) (5.40) against central differences, and the
// state prediction against pose_math's quaternion integrators (2.70) (2.71).
#include <gtest/gtest.h>

#include <functional>

#include "pose_ekf/core/process_model.h"
#include "pose_math/quaternion.h"
#include "state_jacobian.h"

namespace pose_ekf {
namespace {

struct JacobianCase {
  QuatIntegration integration;
  int n;
  double omega_scale;
  double dt;
};

class TransitionJacobianTest : public ::testing::TestWithParam<JacobianCase> {};

TEST_P(TransitionJacobianTest, MatchesNumeric) {
  const JacobianCase c = GetParam();
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const StateVector x = RandomState(c.n, seed, c.omega_scale);
    const Eigen::MatrixXd F = TransitionJacobian(x, c.dt, c.integration);
    const Eigen::MatrixXd Fn = NumericJacobian(
        [&](const StateVector& s) { return Eigen::VectorXd(PropagateState(s, c.dt, c.integration)); }, x, c.n);
    EXPECT_LT((F - Fn).cwiseAbs().maxCoeff(), 1e-8) << "seed " << seed << "\nF\n" << F << "\nnumeric\n" << Fn;
  }
}

INSTANTIATE_TEST_SUITE_P(Integrations, TransitionJacobianTest,
                         ::testing::Values(JacobianCase{QuatIntegration::kFirstOrder, 16, 3.0, 0.01},
                                           JacobianCase{QuatIntegration::kFirstOrder, 19, 3.0, 0.05},
                                           JacobianCase{QuatIntegration::kExact, 16, 3.0, 0.01},
                                           JacobianCase{QuatIntegration::kExact, 16, 20.0, 0.05},
                                           JacobianCase{QuatIntegration::kExact, 19, 1e-7, 0.01}));  // series branch

// The banded product against the dense one, for every state size, both integrations, with damping.
TEST(ProcessModel, PropagateCovarianceEqualsTheDenseProduct) {
  for (int n : {kBaseStates, kBaseStates + 3, kMaxStates})
    for (QuatIntegration integration : {QuatIntegration::kFirstOrder, QuatIntegration::kExact})
      for (double tau : {0.0, 0.4}) {
        const StateVector x = RandomState(n, unsigned(n), 3.0);
        const StateMatrix F = TransitionJacobian(x, 0.01, integration, tau, tau);
        const Eigen::MatrixXd A = Eigen::MatrixXd::Random(n, n);
        const StateMatrix P = A * A.transpose() + Eigen::MatrixXd::Identity(n, n);
        const Eigen::MatrixXd dense = F * P * F.transpose();
        EXPECT_LT((PropagateCovariance(F, P) - dense).cwiseAbs().maxCoeff(), 1e-12 * dense.cwiseAbs().maxCoeff())
            << "n " << n << ", tau " << tau;
      }
}

TEST(ProcessModel, QuaternionMatchesPoseMathIntegrators) {
  const StateVector x = RandomState(16, 7, 4.0);
  const Eigen::Vector4d q = x.segment<4>(kQ);
  const Eigen::Vector3d w = x.segment<3>(kW);
  const double dt = 0.02;
  const Eigen::Vector4d first = PropagateState(x, dt, QuatIntegration::kFirstOrder).segment<4>(kQ).normalized();
  const Eigen::Vector4d exact = PropagateState(x, dt, QuatIntegration::kExact).segment<4>(kQ);
  EXPECT_LT((first - pose_math::IntegrateFirstOrder(q, w, dt)).norm(), 1e-12);
  EXPECT_LT((exact - pose_math::IntegrateExact(q, w, dt)).norm(), 1e-12);
  EXPECT_NEAR(exact.norm(), 1.0, 1e-12);  // (2.71) preserves the norm
}

TEST(ProcessModel, ConstantAccelerationTranslation) {
  StateVector x = StateVector::Zero(16);
  x[kQ] = 1.0;
  x.segment<3>(kP) << 1, 2, 3;
  x.segment<3>(kV) << 0.5, 0, -1;
  x.segment<3>(kA) << 0, 2, 0;
  const StateVector y = PropagateState(x, 0.5, QuatIntegration::kFirstOrder);
  EXPECT_LT((y.segment<3>(kP) - Eigen::Vector3d(1.25, 2.25, 2.5)).norm(), 1e-15);
  EXPECT_LT((y.segment<3>(kV) - Eigen::Vector3d(0.5, 1.0, -1.0)).norm(), 1e-15);
}

TEST(ProcessModel, NoiseGrowsLinearlyWithTime) {
  EkfConfig c;
  c.estimate_gyro_bias = true;
  const StateMatrix q1 = ProcessNoise(c, 19, 0.01), q2 = ProcessNoise(c, 19, 0.02);
  EXPECT_LT((q2 - 2.0 * q1).norm(), 1e-15);
  EXPECT_DOUBLE_EQ(q1(kA, kA), 0.01 * c.sigma_a_m_s2_per_sqrt_s * c.sigma_a_m_s2_per_sqrt_s);
  EXPECT_DOUBLE_EQ(q1(kB + 2, kB + 2), 0.01 * c.sigma_gyro_bias_rad_s_per_sqrt_s * c.sigma_gyro_bias_rad_s_per_sqrt_s);
}

class AccelJacobianTest : public ::testing::TestWithParam<AccelMode> {};

TEST_P(AccelJacobianTest, MatchesNumericIncludingNonUnitQuaternion) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    StateVector x = RandomState(16, seed, 1.0);
    x.segment<4>(kQ) *= 1.0 + 0.1 * seed;  // the general form (2.36) holds off the unit sphere too
    const Eigen::MatrixXd H = AccelJacobian(x, 9.81, GetParam());
    const Eigen::MatrixXd Hn =
        NumericJacobian([&](const StateVector& s) { return Eigen::VectorXd(AccelModel(s, 9.81, GetParam())); }, x, 3);
    EXPECT_LT((H - Hn).cwiseAbs().maxCoeff(), 1e-7) << "seed " << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(Modes, AccelJacobianTest,
                         ::testing::Values(AccelMode::kOrientation, AccelMode::kPositionAndOrientation));

TEST(ProcessModel, AccelModelIsGravityInCameraFrame) {
  StateVector x = StateVector::Zero(16);
  // Camera rotated 90° about x: camera y axis = cones z... R = RotX(90°).
  x.segment<4>(kQ) << std::sqrt(0.5), std::sqrt(0.5), 0, 0;
  const Eigen::Vector3d h = AccelModel(x, 9.81, AccelMode::kOrientation);
  // Rᵀ [0 0 g]: cones z expressed in camera axes is -y... RotX(90) maps y->z, so z_cones = y_camera.
  EXPECT_LT((h - Eigen::Vector3d(0, 9.81, 0)).norm(), 1e-12);
  x.segment<3>(kA) << 1, 0, 0;
  EXPECT_LT((AccelModel(x, 9.81, AccelMode::kPositionAndOrientation) - Eigen::Vector3d(1, 9.81, 0)).norm(), 1e-12);
}

}  // namespace
}  // namespace pose_ekf
