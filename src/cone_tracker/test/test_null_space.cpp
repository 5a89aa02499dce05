// MDLT, 3-simplex and EPnP on noise-free data, and their Jacobians.
#include "../src/pose/null_space.h"
#include "pose_math/rotation.h"
#include "test_util.h"

namespace cone_tracker {
namespace {

constexpr double kExact = 1e-9;

pose_math::Pose Perturbed(const pose_math::Pose& T) {
  pose_math::Pose P = T;
  P.q = pose_math::Multiply(pose_math::Quat(0.995, 0.05, -0.06, 0.04).normalized(), P.q);
  P.t += Eigen::Vector3d(0.02, -0.03, 0.05);
  return P;
}

TEST(Mdlt, LinearAndGaussNewtonRecoverExactPoseInBothSpaces) {
  for (const sim::Case& k : NoiseFreeCases(10)) {
    const Correspondences c = ToCorrespondences(k);
    for (const ErrorSpace space : {ErrorSpace::kImage, ErrorSpace::kObject}) {
      const Estimate linear = MdltLinear(c, space);
      ASSERT_TRUE(linear.ok) << linear.error;
      EXPECT_TRUE(PoseNear(linear.T_camera_model, k.T_camera_model, kExact));
      const Estimate gn = MdltGaussNewton(c, space, Perturbed(k.T_camera_model));
      ASSERT_TRUE(gn.ok);
      EXPECT_TRUE(gn.converged);
      EXPECT_TRUE(PoseNear(gn.T_camera_model, k.T_camera_model, kExact));
    }
  }
}

TEST(Simplex, LinearAndGaussNewtonRecoverExactPoseInBothSpaces) {
  for (const sim::Case& k : NoiseFreeCases(11)) {
    const Correspondences c = ToCorrespondences(k);
    for (const ErrorSpace space : {ErrorSpace::kImage, ErrorSpace::kObject}) {
      const Estimate linear = SimplexLinear(c, space);
      ASSERT_TRUE(linear.ok) << linear.error;
      EXPECT_TRUE(PoseNear(linear.T_camera_model, k.T_camera_model, kExact));
      const Estimate gn = SimplexGaussNewton(c, space, Perturbed(k.T_camera_model));
      ASSERT_TRUE(gn.ok);
      EXPECT_TRUE(gn.converged);
      EXPECT_TRUE(PoseNear(gn.T_camera_model, k.T_camera_model, kExact));
    }
  }
}

TEST(Epnp, LinearAndGaussNewtonRecoverExactPose) {
  for (const sim::Case& k : NoiseFreeCases(12)) {
    const Correspondences c = ToCorrespondences(k);
    const Estimate linear = EpnpLinear(c);
    ASSERT_TRUE(linear.ok) << linear.error;
    EXPECT_TRUE(PoseNear(linear.T_camera_model, k.T_camera_model, kExact));
    const Estimate gn = EpnpGaussNewton(c);
    ASSERT_TRUE(gn.ok) << gn.error;
    EXPECT_TRUE(PoseNear(gn.T_camera_model, k.T_camera_model, kExact));
  }
}

TEST(Ceres, RefinementRecoversExactPose) {
  for (const sim::Case& k : NoiseFreeCases(13)) {
    const Estimate e = CeresRefine(ToCorrespondences(k), Perturbed(k.T_camera_model), false, 2.0, 100);
    ASSERT_TRUE(e.ok) << e.error;
    EXPECT_TRUE(PoseNear(e.T_camera_model, k.T_camera_model, kExact));
  }
}

// dv/dΘ of both null-space parameterisations against central differences of
// v(Rz(α)Ry(β)Rx(γ) R, t + δt) at Θ = 0.
void CheckParamJacobian(NullSpaceParam param) {
  std::mt19937 rng(14);
  const pose_math::Pose T = sim::RandomRotationPose(rng, Eigen::Vector3d(0.1, 0.2, 1.5));
  const Eigen::Matrix3d R = RotationOf(T);
  Eigen::Matrix3d dR[3];
  LeftEulerDerivatives(R, dR);
  Vector12d v;
  Eigen::Matrix<double, 12, 6> analytic;
  param(R, T.t, dR, &v, &analytic);
  const double h = 1e-6;
  for (int k = 0; k < 6; ++k) {
    Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
    d(k) = h;
    const auto eval = [&](double sign) {
      const Eigen::Matrix3d Rk =
          pose_math::RotZ(sign * d(0)) * pose_math::RotY(sign * d(1)) * pose_math::RotX(sign * d(2)) * R;
      Vector12d out;
      param(Rk, T.t + sign * d.tail<3>(), dR, &out, nullptr);
      return out;
    };
    const Vector12d numeric = (eval(1.0) - eval(-1.0)) / (2 * h);
    EXPECT_LT((numeric - analytic.col(k)).norm(), 1e-8) << "column " << k;
  }
}

TEST(NullSpaceGaussNewton, AnalyticJacobiansMatchNumeric) {
  CheckParamJacobian(&MdltParam);
  CheckParamJacobian(&TriadParam);
}

TEST(EulerDerivatives, MatchNumeric) {
  const double a = 0.3, b = -0.7, g = 1.1, h = 1e-6;
  Eigen::Matrix3d dR[3];
  EulerRotationDerivatives(a, b, g, dR);
  const auto R = [](double x, double y, double z) -> Eigen::Matrix3d { return pose_math::RotZ(x) * pose_math::RotY(y) * pose_math::RotX(z); };
  EXPECT_LT(((R(a + h, b, g) - R(a - h, b, g)) / (2 * h) - dR[0]).norm(), 1e-9);
  EXPECT_LT(((R(a, b + h, g) - R(a, b - h, g)) / (2 * h) - dR[1]).norm(), 1e-9);
  EXPECT_LT(((R(a, b, g + h) - R(a, b, g - h)) / (2 * h) - dR[2]).norm(), 1e-9);
}

TEST(ReducedMeasurementMatrix, HasTheSameNormalMatrix) {
  std::mt19937 rng(15);
  const Eigen::MatrixXd M = Eigen::MatrixXd::Random(30, 12);
  const Matrix12d reduced = DecomposeMeasurementMatrix(M).reduced;
  EXPECT_LT((reduced.transpose() * reduced - M.transpose() * M).norm(), 1e-10 * (M.transpose() * M).norm());  // (4.80)
}

}  // namespace
}  // namespace cone_tracker
