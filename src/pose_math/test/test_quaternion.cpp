#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "pose_math/quaternion.h"
#include "pose_math/rotation.h"
#include "test_util.h"

namespace pose_math {
namespace {

TEST(Quaternion, ThesisOrderIsScalarFirstAndEigenIsNot) {
  const Eigen::Quaterniond e(1.0, 2.0, 3.0, 4.0);  // Eigen's constructor is (w, x, y, z)
  EXPECT_EQ(ThesisFromEigen(e), Quat(1.0, 2.0, 3.0, 4.0));
  EXPECT_EQ(e.coeffs(), Eigen::Vector4d(2.0, 3.0, 4.0, 1.0));  // ...but its storage is (x, y, z, w)
  const Eigen::Quaterniond back = EigenFromThesis(Quat(1.0, 2.0, 3.0, 4.0));
  EXPECT_EQ(back.w(), 1.0);
  EXPECT_EQ(back.x(), 2.0);
  EXPECT_EQ(back.z(), 4.0);
}

TEST(Quaternion, HamiltonProductIdentities) {  // (2.40)
  const Quat one(1, 0, 0, 0), i(0, 1, 0, 0), j(0, 0, 1, 0), k(0, 0, 0, 1);
  EXPECT_EQ(Multiply(i, j), k);
  EXPECT_EQ(Multiply(j, i), Quat(-k));
  EXPECT_EQ(Multiply(j, k), i);
  EXPECT_EQ(Multiply(k, i), j);
  EXPECT_EQ(Multiply(i, i), Quat(-one));
  EXPECT_EQ(Multiply(Multiply(i, j), k), Quat(-one));  // ijk = −1
}

TEST(Quaternion, LeftAndRightMatricesMatchTheProduct) {  // (2.44)
  test::Random rnd(1);
  for (int n = 0; n < 100; ++n) {
    const Quat p = rnd.UnitQuat() * 1.7, q = rnd.UnitQuat() * 0.3;
    EXPECT_LT((LeftMatrix(p) * q - Multiply(p, q)).norm(), 1e-15);
    EXPECT_LT((RightMatrix(q) * p - Multiply(p, q)).norm(), 1e-15);
    const Eigen::Quaterniond e = EigenFromThesis(p) * EigenFromThesis(q);
    EXPECT_LT((ThesisFromEigen(e) - Multiply(p, q)).norm(), 1e-15);
  }
}

TEST(Quaternion, RotateAgreesWithMatrixAndEigen) {  // (2.42)
  test::Random rnd(2);
  for (int n = 0; n < 100; ++n) {
    const Quat q = rnd.UnitQuat();
    const Eigen::Vector3d v = rnd.Vector3();
    EXPECT_LT((Rotate(q, v) - RotationFromQuat(q) * v).norm(), 1e-14);
    EXPECT_LT((Rotate(q, v) - EigenFromThesis(q) * v).norm(), 1e-14);
    const Quat qv = Multiply(Multiply(q, Quat(0, v.x(), v.y(), v.z())), Conjugate(q));
    EXPECT_LT((Rotate(q, v) - qv.tail<3>()).norm(), 1e-14);
  }
}

TEST(Quaternion, SkewIsTheCrossProduct) {  // (2.50)
  const Eigen::Vector3d w(1, -2, 3), v(0.5, 4, -1);
  EXPECT_LT((Skew(w) * v - w.cross(v)).norm(), 1e-15);
  EXPECT_LT((Skew(w) + Skew(w).transpose()).norm(), 1e-15);
}

TEST(Quaternion, OmegaMatrixIsRightMatrixOfPureQuaternion) {  // (2.69)
  const Eigen::Vector3d w(0.1, -0.2, 0.3);
  // Rows written out from (2.69): [0 −ωx −ωy −ωz; ωx 0 ωz −ωy; ωy −ωz 0 ωx; ωz ωy −ωx 0].
  Eigen::Matrix4d from_thesis;
  from_thesis << 0, -w.x(), -w.y(), -w.z(), w.x(), 0, w.z(), -w.y(), w.y(), -w.z(), 0, w.x(), w.z(), w.y(), -w.x(), 0;
  EXPECT_LT((OmegaMatrix(w) - from_thesis).norm(), 1e-15);
}

TEST(Quaternion, ExactIntegrationMatchesClosedForm) {  // (2.71)
  test::Random rnd(3);
  const Quat q0 = rnd.UnitQuat();
  const Eigen::Vector3d w(0.7, -1.9, 3.1);  // rad/s, body frame
  Quat q = q0;
  for (int k = 0; k < 1000; ++k) q = IntegrateExact(q, w, 0.01);
  const Quat expected = Multiply(q0, QuatFromRotationVector(w * 10.0));
  EXPECT_LT((CanonicalSign(q) - CanonicalSign(expected)).norm(), 1e-12);
}

TEST(Quaternion, FirstOrderIntegrationConvergesAtFirstOrder) {  // (2.70)
  const Eigen::Vector3d w(0.0, 0.0, 3.0);
  const Quat expected = QuatFromRotationVector(w * 1.0);
  double prev_err = 0.0;
  for (int steps : {100, 1000}) {
    Quat q = IdentityQuat();
    for (int k = 0; k < steps; ++k) q = IntegrateFirstOrder(q, w, 1.0 / steps);
    const double err = (q - expected).norm();
    EXPECT_LT(err, 3.0 / steps);
    if (prev_err > 0.0) {
      EXPECT_LT(err, prev_err);
    }
    prev_err = err;
  }
}

TEST(Quaternion, ExactIntegrationAtZeroRateIsIdentity) {
  const Quat q = Quat(0.5, 0.5, -0.5, 0.5);
  EXPECT_LT((IntegrateExact(q, Eigen::Vector3d::Zero(), 0.01) - q).norm(), 1e-16);
  const Eigen::Vector3d tiny(1e-12, 0, 0);
  EXPECT_LT((IntegrateExact(q, tiny, 0.01) - IntegrateFirstOrder(q, tiny, 0.01)).norm(), 1e-16);
}

TEST(Quaternion, RotateJacobianMatchesNumeric) {
  test::Random rnd(4);
  for (int n = 0; n < 20; ++n) {
    const Quat q = rnd.UnitQuat() * 1.3;  // general (non-unit) quaternion, as (2.36) allows
    const Eigen::Vector3d v = rnd.Vector3();
    const auto f = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
      const double q0 = x[0];
      const Eigen::Vector3d qv = x.tail<3>();
      return (q0 * q0 - qv.squaredNorm()) * v + 2.0 * qv.dot(v) * qv + 2.0 * q0 * qv.cross(v);  // (2.36) R(q) v
    };
    EXPECT_LT((RotateJacobianWrtQuat(q, v) - test::NumericJacobian(f, q)).norm(), 1e-8);
  }
}

TEST(Quaternion, InvalidInputIsRejectedAndNonUnitIsNormalised) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(NormalizedQuat(Quat(nan, 0, 0, 0)), std::invalid_argument);
  EXPECT_THROW(NormalizedQuat(Quat(1, inf, 0, 0)), std::invalid_argument);
  EXPECT_THROW(NormalizedQuat(Quat::Zero()), std::invalid_argument);
  EXPECT_THROW(Rotate(Quat(nan, 0, 0, 0), Eigen::Vector3d::UnitX()), std::invalid_argument);
  EXPECT_THROW(IntegrateExact(IdentityQuat(), Eigen::Vector3d(nan, 0, 0), 0.01), std::invalid_argument);
  EXPECT_THROW(IntegrateFirstOrder(IdentityQuat(), Eigen::Vector3d::Zero(), nan), std::invalid_argument);
  const Quat q(0.2, -0.4, 0.1, 0.9);
  EXPECT_LT((Rotate(q * 5.0, Eigen::Vector3d(1, 2, 3)) - Rotate(q, Eigen::Vector3d(1, 2, 3))).norm(), 1e-14);
  EXPECT_NEAR(NormalizedQuat(q * 5.0).norm(), 1.0, 1e-15);
  try {
    RotationFromQuat(Quat(nan, 0, 0, 0));
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("RotationFromQuat"), std::string::npos);
  }
}

}  // namespace
}  // namespace pose_math
