#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "pose_math/rotation.h"
#include "test_util.h"

namespace pose_math {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kRandomRotations = 10000;

double MaxAbs(const Eigen::MatrixXd& m) { return m.cwiseAbs().maxCoeff(); }

// Rotation vectors θk are compared rather than (θ, k) so that θ = 0 has no axis
// ambiguity; at θ = π, ±k are both valid and are compared as rotations.
double RotationDistance(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) { return MaxAbs(a - b); }

TEST(Rotation, KnownValues) {
  const double h = std::sqrt(0.5);
  // 90° about z (2.17) ↔ q = [cos 45°, 0, 0, sin 45°] (2.34).
  const Eigen::Matrix3d Rz = RotZ(kPi / 2);
  EXPECT_LT((QuatFromRotation(Rz) - Quat(h, 0, 0, h)).norm(), 1e-15);
  Eigen::Matrix3d expected;
  expected << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_LT(MaxAbs(RotationFromQuat(Quat(h, 0, 0, h)) - expected), 1e-15);
  // 180° about x: q = [0, 1, 0, 0]; the largest-diagonal branch is qx (2.38).
  EXPECT_LT((QuatFromRotation(RotX(kPi)) - Quat(0, 1, 0, 0)).norm(), 1e-15);
  const AngleAxis aa = AngleAxisFromRotation(RotY(2.0));
  EXPECT_NEAR(aa.angle_rad, 2.0, 1e-15);
  EXPECT_LT((aa.axis - Eigen::Vector3d::UnitY()).norm(), 1e-15);
  // ZYX: Rz(0.1) Ry(0.2) Rx(0.3) (2.19).
  const EulerZyx e = EulerZyxFromRotation(RotZ(0.1) * RotY(0.2) * RotX(0.3));
  EXPECT_NEAR(e.alpha_rad, 0.1, 1e-15);
  EXPECT_NEAR(e.beta_rad, 0.2, 1e-15);
  EXPECT_NEAR(e.gamma_rad, 0.3, 1e-15);
  EXPECT_FALSE(e.singular);
}

TEST(Rotation, QuaternionAndMatrixAgreeWithEigen) {
  test::Random rnd(10);
  for (int n = 0; n < 1000; ++n) {
    const Quat q = rnd.UnitQuat();
    EXPECT_LT(MaxAbs(RotationFromQuat(q) - EigenFromThesis(q).toRotationMatrix()), 4e-15);
  }
}

TEST(Rotation, RoundTripsOverRandomRotations) {
  test::Random rnd(11);
  double err_R_q_R = 0, err_q_R_q = 0, err_R_aa_R = 0, err_aa_R_aa = 0, err_q_aa_q = 0;
  for (int n = 0; n < kRandomRotations; ++n) {
    const Quat q = CanonicalSign(rnd.UnitQuat());
    const Eigen::Matrix3d R = RotationFromQuat(q);
    err_R_q_R = std::max(err_R_q_R, MaxAbs(RotationFromQuat(QuatFromRotation(R)) - R));
    err_q_R_q = std::max(err_q_R_q, (QuatFromRotation(R) - q).cwiseAbs().maxCoeff());
    const AngleAxis aa = AngleAxisFromRotation(R);
    err_R_aa_R = std::max(err_R_aa_R, MaxAbs(RotationFromAngleAxis(aa) - R));
    const AngleAxis aa2 = AngleAxisFromRotation(RotationFromAngleAxis(aa));
    err_aa_R_aa = std::max(err_aa_R_aa, (aa2.angle_rad * aa2.axis - aa.angle_rad * aa.axis).cwiseAbs().maxCoeff());
    err_q_aa_q = std::max(err_q_aa_q, (QuatFromAngleAxis(AngleAxisFromQuat(q)) - q).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(err_R_q_R, 1e-12);
  EXPECT_LT(err_q_R_q, 1e-12);
  EXPECT_LT(err_R_aa_R, 1e-12);
  EXPECT_LT(err_aa_R_aa, 1e-12);
  EXPECT_LT(err_q_aa_q, 1e-12);
  RecordProperty("max_err_R_q_R", std::to_string(err_R_q_R));
}

TEST(Rotation, AngleAxisNearZero) {  // θ = 0: any axis is valid (2.23)
  test::Random rnd(12);
  EXPECT_EQ(AngleAxisFromRotation(Eigen::Matrix3d::Identity()).angle_rad, 0.0);
  EXPECT_EQ(RotationFromAngleAxis({0.0, Eigen::Vector3d::Zero()}), Eigen::Matrix3d::Identity());
  for (double theta : {1e-9, 3e-10, 1e-12, 1e-15}) {
    for (int n = 0; n < 100; ++n) {
      const AngleAxis in{theta, rnd.UnitVector()};
      const Eigen::Matrix3d R = RotationFromAngleAxis(in);
      const AngleAxis out = AngleAxisFromRotation(R);
      EXPECT_NEAR(out.angle_rad, theta, 1e-15);
      EXPECT_LT(RotationDistance(RotationFromAngleAxis(out), R), 1e-15);
      EXPECT_LT((RotationVectorFromQuat(QuatFromRotation(R)) - theta * in.axis).norm(), 1e-15);
    }
  }
}

TEST(Rotation, AngleAxisNearPi) {  // θ = π: the diagonal extraction (2.26) (2.27) (2.28)
  test::Random rnd(13);
  for (double dtheta : {0.0, 1e-12, 1e-9, 1e-6}) {
    for (int n = 0; n < 1000; ++n) {
      const AngleAxis in{kPi - dtheta, rnd.UnitVector()};
      const Eigen::Matrix3d R = RotationFromAngleAxis(in);
      const AngleAxis out = AngleAxisFromRotation(R);
      EXPECT_NEAR(out.angle_rad, in.angle_rad, 1e-12);
      EXPECT_LT(RotationDistance(RotationFromAngleAxis(out), R), 1e-12);
      // Off π the axis is unique; at π it is unique up to sign.
      const double axis_err = dtheta > 0.0 ? (out.axis - in.axis).norm()
                                           : std::min((out.axis - in.axis).norm(), (out.axis + in.axis).norm());
      EXPECT_LT(axis_err, dtheta > 0.0 ? 1e-6 : 1e-12) << "dθ = " << dtheta;
      EXPECT_LT(RotationDistance(RotationFromQuat(QuatFromRotation(R)), R), 1e-12);
    }
  }
}

TEST(Rotation, AngleAxisAxisIsExactJustBelowPi) {
  // The R − Rᵀ formula (2.25) would lose all precision here; the diagonal one does not.
  const Eigen::Vector3d k = Eigen::Vector3d(1, 2, 3).normalized();
  const AngleAxis out = AngleAxisFromRotation(RotationFromAngleAxis({kPi - 1e-9, k}));
  EXPECT_LT((out.axis - k).norm(), 1e-7);  // sign resolved from a 1e-9 antisymmetric part
}

TEST(Rotation, EulerRoundTrip) {
  test::Random rnd(14);
  double err = 0;
  for (int n = 0; n < kRandomRotations; ++n) {
    const EulerZyx in{rnd.Uniform(-kPi, kPi), rnd.Uniform(-kPi / 2 + 1e-3, kPi / 2 - 1e-3), rnd.Uniform(-kPi, kPi)};
    const EulerZyx out = EulerZyxFromRotation(RotationFromEulerZyx(in));
    EXPECT_FALSE(out.singular);
    err = std::max({err, std::abs(out.alpha_rad - in.alpha_rad), std::abs(out.beta_rad - in.beta_rad),
                    std::abs(out.gamma_rad - in.gamma_rad)});
  }
  EXPECT_LT(err, 1e-12);
}

TEST(Rotation, EulerSingularityIsReportedNotHidden) {  // |β| = π/2 (section 2.2.1)
  for (double sign : {1.0, -1.0}) {
    for (double off : {0.0, 1e-12, 1e-9}) {
      const EulerZyx in{0.4, sign * (kPi / 2 - off), -1.1};
      const Eigen::Matrix3d R = RotationFromEulerZyx(in);
      const EulerZyx out = EulerZyxFromRotation(R);
      EXPECT_TRUE(out.singular) << "β = " << in.beta_rad;
      EXPECT_EQ(out.alpha_rad, 0.0);
      EXPECT_NEAR(out.beta_rad, in.beta_rad, 1e-12);
      // The rotation is still represented, to the size of cos β.
      EXPECT_LT(MaxAbs(RotationFromEulerZyx(out) - R), 1e-8);
    }
  }
  // Well away from the singularity it is not reported.
  EXPECT_FALSE(EulerZyxFromRotation(RotationFromEulerZyx({0.4, kPi / 2 - 1e-5, -1.1})).singular);
}

TEST(Rotation, NearestRotationFixesTheDeterminant) {
  test::Random rnd(15);
  const Eigen::Matrix3d R = RotationFromQuat(rnd.UnitQuat());
  Eigen::Matrix3d noisy = R;
  noisy(0, 1) += 1e-3;
  noisy(2, 2) -= 2e-3;
  const Eigen::Matrix3d fixed = NearestRotation(noisy);
  EXPECT_NEAR(fixed.determinant(), 1.0, 1e-12);
  EXPECT_LT(MaxAbs(fixed.transpose() * fixed - Eigen::Matrix3d::Identity()), 1e-12);
  EXPECT_LT(MaxAbs(fixed - R), 3e-3);
  const Eigen::Matrix3d reflection = Eigen::Vector3d(1, 1, -1).asDiagonal();
  EXPECT_NEAR(NearestRotation(reflection).determinant(), 1.0, 1e-12);
}

TEST(Rotation, NonFiniteInputThrows) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::Matrix3d bad = Eigen::Matrix3d::Identity();
  bad(1, 2) = nan;
  EXPECT_THROW(QuatFromRotation(bad), std::invalid_argument);
  EXPECT_THROW(AngleAxisFromRotation(bad), std::invalid_argument);
  EXPECT_THROW(EulerZyxFromRotation(bad), std::invalid_argument);
  EXPECT_THROW(NearestRotation(bad), std::invalid_argument);
  EXPECT_THROW(RotationFromAngleAxis({nan, Eigen::Vector3d::UnitX()}), std::invalid_argument);
  EXPECT_THROW(RotationFromAngleAxis({1.0, Eigen::Vector3d::Zero()}), std::invalid_argument);
  EXPECT_THROW(QuatFromAngleAxis({1.0, Eigen::Vector3d(nan, 0, 0)}), std::invalid_argument);
  // A non-unit axis is normalised.
  EXPECT_LT(MaxAbs(RotationFromAngleAxis({0.5, Eigen::Vector3d(0, 0, 7)}) - RotZ(0.5)), 1e-15);
}

}  // namespace
}  // namespace pose_math
