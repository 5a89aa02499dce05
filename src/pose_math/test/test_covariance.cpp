#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

#include "pose_math/covariance.h"
#include "pose_math/rotation.h"
#include "test_util.h"

namespace pose_math {
namespace {

TEST(Covariance, HouseholderNullSpace) {  // (5.69) (5.70) (5.71)
  test::Random rnd(30);
  std::vector<Quat> qs = {IdentityQuat(), Quat(-1, 0, 0, 0), Quat(0, 1, 0, 0), Quat(0, 0, 0, -1)};
  for (int n = 0; n < 100; ++n) qs.push_back(rnd.UnitQuat());
  for (const Quat& q : qs) {
    const Eigen::Matrix<double, 7, 6> N = QuaternionNullSpace(q);
    Vector7d D = Vector7d::Zero();
    D.head<4>() = q;
    EXPECT_LT((D.transpose() * N).norm(), 1e-15);
    EXPECT_LT((N.transpose() * N - Eigen::Matrix<double, 6, 6>::Identity()).norm(), 1e-14);
    // The translation dimensions are free (5.70): they lie in the null space.
    EXPECT_LT(((N * N.transpose()).bottomRightCorner<3, 3>() - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  }
}

TEST(Covariance, KnownValueAtIdentity) {
  Matrix6d cov6 = Matrix6d::Zero();
  cov6.diagonal() << 1e-4, 4e-4, 9e-4, 1e-2, 4e-2, 9e-2;  // x y z (m²), rx ry rz (rad²)
  const Matrix7d cov7 = CovarianceThesisFromRos(IdentityQuat(), cov6);
  // δq = [0, δθ/2]: quaternion vector variances are a quarter of the angle variances.
  EXPECT_NEAR(cov7(0, 0), 0.0, 1e-18);
  EXPECT_NEAR(cov7(1, 1), 0.25e-2, 1e-15);
  EXPECT_NEAR(cov7(3, 3), 0.25 * 9e-2, 1e-15);
  EXPECT_NEAR(cov7(4, 4), 1e-4, 1e-18);
  EXPECT_NEAR(cov7(6, 6), 9e-4, 1e-18);
}

TEST(Covariance, PerturbationIsFixedAxisLeftMultiplication) {
  // G(q) must be d/dδθ of exp(δθ) ⊗ q at δθ = 0: rotation about the parent's axes.
  test::Random rnd(31);
  for (int n = 0; n < 20; ++n) {
    const Quat q = rnd.UnitQuat();
    const auto f = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd { return Multiply(QuatFromRotationVector(d), q); };
    EXPECT_LT((RotationPerturbationToQuat(q) - test::NumericJacobian(f, Eigen::Vector3d::Zero())).norm(), 1e-9);
  }
}

TEST(Covariance, RoundTripSevenSixSeven) {
  test::Random rnd(32);
  for (int n = 0; n < 1000; ++n) {
    const Quat q = rnd.UnitQuat();
    const Eigen::Matrix<double, 7, 6> N = QuaternionNullSpace(q);
    const double scale = std::pow(10.0, rnd.Uniform(-8, 0));
    const Matrix7d cov7 = N * rnd.Spd(6, 0.01 * scale, scale) * N.transpose();
    const Matrix7d back = CovarianceThesisFromRos(q, CovarianceRosFromThesis(q, cov7));
    EXPECT_LT((back - cov7).norm() / cov7.norm(), 1e-9);
  }
}

TEST(Covariance, RoundTripSixSevenSix) {
  test::Random rnd(33);
  for (int n = 0; n < 1000; ++n) {
    const Quat q = rnd.UnitQuat();
    const Eigen::MatrixXd cov6 = rnd.Spd(6, 1e-6, 1.0);
    const Matrix6d back = CovarianceRosFromThesis(q, CovarianceThesisFromRos(q, cov6));
    EXPECT_LT((back - cov6).norm() / cov6.norm(), 1e-12);
  }
}

TEST(Covariance, RadialComponentIsRemoved) {
  test::Random rnd(34);
  const Quat q = rnd.UnitQuat();
  Matrix7d cov7 = Matrix7d::Zero();
  cov7.topLeftCorner<4, 4>() = q * q.transpose();  // purely along q̂: no rotation at all
  EXPECT_LT(CovarianceRosFromThesis(q, cov7).norm(), 1e-15);
  EXPECT_LT(ProjectToTangent(q, cov7).norm(), 1e-15);
}

TEST(Covariance, ConstrainedPoseCovarianceSatisfiesTheConstraint) {  // (5.68) (5.74)
  test::Random rnd(35);
  const Quat q = rnd.UnitQuat();
  Eigen::MatrixXd A(18, 7);
  for (int i = 0; i < A.size(); ++i) A.data()[i] = rnd.Normal();
  const double sigma2 = 4.0;
  const Eigen::MatrixXd noise = sigma2 * Eigen::MatrixXd::Identity(18, 18);
  const Matrix7d cov = ConstrainedPoseCovariance(q, A, noise);
  Vector7d D = Vector7d::Zero();
  D.head<4>() = q;
  EXPECT_LT((D.transpose() * cov).norm(), 1e-12 * cov.norm());
  // With white noise, C Σn Cᵀ reduces to σ² N (NᵀAᵀAN)⁻¹ Nᵀ.
  const Eigen::Matrix<double, 7, 6> N = QuaternionNullSpace(q);
  const Eigen::MatrixXd expected = sigma2 * N * (N.transpose() * A.transpose() * A * N).inverse() * N.transpose();
  EXPECT_LT((cov - expected).norm() / expected.norm(), 1e-12);
}

TEST(Covariance, BadInputIsRejected) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(CovarianceRosFromThesis(Quat(nan, 0, 0, 0), Matrix7d::Identity()), std::invalid_argument);
  EXPECT_THROW(CovarianceThesisFromRos(Quat::Zero(), Matrix6d::Identity()), std::invalid_argument);
  EXPECT_THROW(
      ConstrainedPoseCovariance(IdentityQuat(), Eigen::MatrixXd::Zero(12, 7), Eigen::MatrixXd::Identity(12, 12)),
      std::invalid_argument);  // rank deficient
  EXPECT_THROW(
      ConstrainedPoseCovariance(IdentityQuat(), Eigen::MatrixXd::Zero(12, 6), Eigen::MatrixXd::Identity(12, 12)),
      std::invalid_argument);  // wrong shape
  Matrix6d cov6 = Matrix6d::Identity();
  cov6(2, 3) = nan;
  EXPECT_FALSE(SymmetrizeCovariance(cov6));
  Matrix6d asym = Matrix6d::Identity();
  asym(0, 1) = 2.0;
  EXPECT_TRUE(SymmetrizeCovariance(asym));
  EXPECT_EQ(asym(1, 0), 1.0);
}

}  // namespace
}  // namespace pose_math
