// P3P, DLT, Horn and Lu–Hager on noise-free data.
#include "test_util.h"

namespace cone_tracker {
namespace {

constexpr double kExact = 1e-9;

TEST(AbsoluteOrientation, SvdAndQuaternionRecoverKnownMotion) {
  std::mt19937 rng(1);
  const pose_math::Pose T = sim::RandomRotationPose(rng, Eigen::Vector3d(0.3, -0.2, 1.5));
  const Eigen::Matrix3Xd model = Eigen::Matrix3Xd::Random(3, 8);
  Eigen::Matrix3Xd camera(3, 8);
  for (int i = 0; i < 8; ++i) camera.col(i) = pose_math::Transform(T, model.col(i));
  EXPECT_TRUE(PoseNear(AbsoluteOrientationSvd(model, camera), T, 1e-12));
  EXPECT_TRUE(PoseNear(AbsoluteOrientationQuat(model, camera), T, 1e-12));
}

TEST(AbsoluteOrientation, SvdDeterminantFixGivesProperRotation) {
  // A mirrored point set: the unconstrained best fit is a reflection.
  Eigen::Matrix3Xd model(3, 4), camera(3, 4);
  model << 1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1;
  camera = model;
  camera.row(2) *= -1.0;
  const pose_math::Pose T = AbsoluteOrientationSvd(model, camera);
  EXPECT_NEAR(RotationOf(T).determinant(), 1.0, 1e-12);
  const pose_math::Pose Tq = AbsoluteOrientationQuat(model, camera);
  EXPECT_NEAR(RotationOf(Tq).determinant(), 1.0, 1e-12);
}

TEST(P3p, RecoversExactPoseAndPicksRootWithExtraPoints) {
  for (const sim::Case& k : NoiseFreeCases(2)) {
    const Estimate e = P3pFischlerBolles(ToCorrespondences(k));
    ASSERT_TRUE(e.ok) << e.error;
    EXPECT_TRUE(PoseNear(e.T_camera_model, k.T_camera_model, kExact));
  }
}

TEST(Dlt, RecoversExactPoseWithOrthogonalRotation) {
  for (const sim::Case& k : NoiseFreeCases(3)) {
    const Estimate e = Dlt(ToCorrespondences(k));
    ASSERT_TRUE(e.ok) << e.error;
    EXPECT_TRUE(PoseNear(e.T_camera_model, k.T_camera_model, kExact));
    EXPECT_LT(e.rotation_nonorthogonality, 1e-9);
  }
}

TEST(Dlt, ReportsNonOrthogonalityUnderNoise) {
  std::mt19937 rng(4);
  const sim::Case k = sim::RandomCloud(rng, 10);
  const Estimate e = Dlt(ToCorrespondences(k, sim::AddNoise(rng, k.image, 5.0)));
  ASSERT_TRUE(e.ok);
  EXPECT_GT(e.rotation_nonorthogonality, 1e-3);  // the thesis's "big problem"
}

TEST(Oia, ConvergesToExactPoseFromItsOwnStartAndFromAGuess) {
  for (const sim::Case& k : NoiseFreeCases(5)) {
    const Correspondences c = ToCorrespondences(k);
    const Estimate own = OrthogonalIteration(c, nullptr, 2000, 0.0);
    ASSERT_TRUE(own.ok);
    EXPECT_TRUE(PoseNear(own.T_camera_model, k.T_camera_model, kExact));
    pose_math::Pose guess = k.T_camera_model;
    guess.q = pose_math::Multiply(guess.q, pose_math::Quat(0.99, 0.1, -0.05, 0.05).normalized());
    const Estimate from_guess = OrthogonalIteration(c, &guess, 2000, 0.0);
    EXPECT_TRUE(PoseNear(from_guess.T_camera_model, k.T_camera_model, kExact));
    EXPECT_TRUE(from_guess.converged);
  }
}

}  // namespace
}  // namespace cone_tracker
