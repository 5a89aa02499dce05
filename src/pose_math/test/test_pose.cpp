#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "pose_math/covariance.h"
#include "pose_math/pose.h"
#include "pose_math/rotation.h"
#include "test_util.h"

namespace pose_math {
namespace {

Pose RandomPose(test::Random& rnd) { return Pose{rnd.UnitQuat(), rnd.Vector3(2.0)}; }

Matrix7d RandomTangentCovariance(test::Random& rnd, const Quat& q) {
  const Eigen::Matrix<double, 7, 6> N = QuaternionNullSpace(q);
  return N * rnd.Spd(6, 1e-4, 1e-2) * N.transpose();
}

TEST(Pose, InvertKnownValue) {
  // Camera 2 m in front of the cones, looking back at them: T_camera_cones.
  const Pose T_camera_cones{QuatFromRotation(RotX(3.14159265358979323846)), Eigen::Vector3d(0, 0, 2)};
  const Pose T_cones_camera = Invert(T_camera_cones);
  EXPECT_LT((T_cones_camera.t - Eigen::Vector3d(0, 0, 2)).norm(), 1e-15);
  const Eigen::Vector3d p_cone(0.3, -0.1, 0.2);
  const Eigen::Vector3d p_cam = Transform(T_camera_cones, p_cone);
  EXPECT_LT((Transform(T_cones_camera, p_cam) - p_cone).norm(), 1e-15);
}

TEST(Pose, ExtrapolateConstantRateIsExactForConstantRates) {
  // A body turning at a constant body rate and moving at a constant velocity: R(t) = R0 Exp(w t), p(t) = p0 + v t.
  test::Random rnd(21);
  const Eigen::Matrix3d R0 = RotationFromQuat(rnd.UnitQuat());
  const Eigen::Vector3d w(0.4, -1.9, 0.7), v(0.3, -0.2, 1.1), p0 = rnd.Vector3(2.0);
  const auto at = [&](double t) {
    return Pose{QuatFromRotation(R0 * Eigen::AngleAxisd(w.norm() * t, w.normalized()).toRotationMatrix()), p0 + v * t};
  };
  const Pose T = ExtrapolateConstantRate(at(0.02), 0.02, at(0.03), 0.03, 0.048);
  EXPECT_LT(RotationErrorRad(T, at(0.048)), 1e-12);
  EXPECT_LT(TranslationError(T, at(0.048)), 1e-12);
  // No span to take rates from: the newest pose as it is.
  const Pose same = ExtrapolateConstantRate(at(0.03), 0.03, at(0.02), 0.02, 0.048);
  EXPECT_LT(RotationErrorRad(same, at(0.02)), 1e-15);
  EXPECT_LT(TranslationError(same, at(0.02)), 1e-15);
}

TEST(Pose, ComposeWithInverseIsIdentity) {
  test::Random rnd(20);
  for (int n = 0; n < 100; ++n) {
    const Pose T = RandomPose(rnd);
    const Pose I = Compose(T, Invert(T));
    EXPECT_LT(RotationErrorRad(I, Pose{}), 1e-14);
    EXPECT_LT(I.t.norm(), 1e-14);
    const Eigen::Vector3d p = rnd.Vector3();
    const Pose T2 = RandomPose(rnd);
    EXPECT_LT((Transform(Compose(T, T2), p) - Transform(T, Transform(T2, p))).norm(), 1e-14);
  }
}

// Analytic Jacobians are checked along the tangent hyperplane, where the
// covariances live (the radial direction only rescales a quaternion).
TEST(Pose, InvertJacobianMatchesNumeric) {
  test::Random rnd(21);
  for (int n = 0; n < 20; ++n) {
    const Pose T = RandomPose(rnd);
    const auto f = [](const Eigen::VectorXd& x) -> Eigen::VectorXd { return ToVector(Invert(FromVector(x))); };
    const Eigen::Matrix<double, 7, 6> N = QuaternionNullSpace(T.q);
    const Eigen::MatrixXd numeric = test::NumericJacobian(f, ToVector(T)) * N;
    EXPECT_LT((InvertJacobian(T) * N - numeric).norm(), 1e-8);
  }
}

TEST(Pose, ComposeJacobiansMatchNumeric) {
  test::Random rnd(22);
  for (int n = 0; n < 20; ++n) {
    const Pose A = RandomPose(rnd), B = RandomPose(rnd);
    Matrix7d Ja, Jb;
    ComposeJacobians(A, B, &Ja, &Jb);
    const auto fa = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return ToVector(Compose(FromVector(x), B)); };
    const auto fb = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return ToVector(Compose(A, FromVector(x))); };
    EXPECT_LT(
        (Ja * QuaternionNullSpace(A.q) - test::NumericJacobian(fa, ToVector(A)) * QuaternionNullSpace(A.q)).norm(),
        1e-8);
    EXPECT_LT(
        (Jb * QuaternionNullSpace(B.q) - test::NumericJacobian(fb, ToVector(B)) * QuaternionNullSpace(B.q)).norm(),
        1e-8);
  }
}

TEST(Pose, CovarianceSurvivesDoubleInversion) {
  test::Random rnd(23);
  for (int n = 0; n < 50; ++n) {
    PoseWithCovariance T{RandomPose(rnd), Matrix7d::Zero()};
    T.pose.q = CanonicalSign(T.pose.q);
    T.cov = RandomTangentCovariance(rnd, T.pose.q);
    const PoseWithCovariance back = Invert(Invert(T));
    EXPECT_LT((back.cov - T.cov).norm(), 1e-12 * T.cov.norm());
    // The inverse's covariance is on the tangent plane of the inverse's quaternion.
    const PoseWithCovariance inv = Invert(T);
    EXPECT_LT((inv.pose.q.transpose() * inv.cov.topLeftCorner<4, 7>()).norm(), 1e-15);
  }
}

TEST(Pose, CovarianceMatchesMonteCarloThroughInversion) {
  // Sample T_camera_cones on its tangent plane, invert each sample, and compare
  // the sample covariance with the first-order propagation. This is the map the
  // tracker uses to hand chapter 4's pose to the EKF.
  test::Random rnd(24);
  PoseWithCovariance T{Pose{QuatFromRotation(RotX(2.8) * RotZ(0.3)), Eigen::Vector3d(0.1, 0.4, 2.5)}, Matrix7d::Zero()};
  const Eigen::Matrix<double, 7, 6> N = QuaternionNullSpace(T.pose.q);
  const Eigen::MatrixXd S6 = rnd.Spd(6, 1e-7, 1e-5);
  T.cov = N * S6 * N.transpose();
  const Eigen::LLT<Eigen::MatrixXd> llt(S6);
  const PoseWithCovariance predicted = Invert(T);
  const int samples = 20000;
  Matrix7d sample_cov = Matrix7d::Zero();
  const Vector7d mean = ToVector(predicted.pose);
  for (int s = 0; s < samples; ++s) {
    Eigen::VectorXd z(6);
    for (int i = 0; i < 6; ++i) z[i] = rnd.Normal();
    const Vector7d x = ToVector(T.pose) + N * (llt.matrixL() * z);
    const Vector7d d = ToVector(Invert(FromVector(x))) - mean;
    sample_cov += d * d.transpose() / samples;
  }
  // Diagonal within 5% (sampling error of a variance with 20000 samples is ~1%).
  for (int i = 0; i < 7; ++i) {
    if (predicted.cov(i, i) < 1e-12) continue;
    EXPECT_NEAR(sample_cov(i, i) / predicted.cov(i, i), 1.0, 0.05) << "index " << i;
  }
}

TEST(Pose, ComposeAddsIndependentCovariances) {
  test::Random rnd(25);
  PoseWithCovariance A{RandomPose(rnd), Matrix7d::Zero()};
  PoseWithCovariance I{Pose{}, Matrix7d::Zero()};
  A.cov = RandomTangentCovariance(rnd, A.pose.q);
  EXPECT_LT((Compose(A, I).cov - A.cov).norm(), 1e-14);
  EXPECT_LT((Compose(I, A).cov - A.cov).norm(), 1e-14);
}

}  // namespace
}  // namespace pose_math
