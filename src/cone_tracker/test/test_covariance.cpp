// Section 5.6: Jacobians against central differences, and the predicted
// covariance against a small Monte Carlo run.
#include <cmath>

#include "cone_tracker/pose/covariance.h"
#include "pose_math/covariance.h"
#include "pose_math/rotation.h"
#include "test_util.h"

namespace cone_tracker {
namespace {

constexpr double kH = 1e-6;

struct Fixture {
  sim::Case k;
  Correspondences c;
};
Fixture MakeSetup(unsigned seed, int points) {
  std::mt19937 rng(seed);
  Fixture s{sim::RandomCloud(rng, points), {}};
  // A noisy observation so object-space residuals are not zero.
  s.c = ToCorrespondences(s.k, sim::AddNoise(rng, s.k.image, 2.0));
  return s;
}

// Directions tangent to the unit sphere at q (where the constrained covariance
// lives) plus the three translations.
std::vector<pose_math::Vector7d> TangentDirections(const pose_math::Quat& q) {
  const Eigen::Matrix<double, 7, 6> N = pose_math::QuaternionNullSpace(q);
  std::vector<pose_math::Vector7d> dirs;
  for (int k = 0; k < 6; ++k) dirs.push_back(N.col(k));
  return dirs;
}

pose_math::Pose Shift(const pose_math::Pose& T, const pose_math::Vector7d& d, double h) {
  pose_math::Pose P;
  P.q = T.q + h * d.head<4>();  // first order equals the normalised quaternion along tangents
  P.t = T.t + h * d.tail<3>();
  return P;
}

TEST(CovarianceJacobians, QuaternionImageAndObjectMatchNumeric) {
  const Fixture s = MakeSetup(20, 6);
  const pose_math::Pose& T = s.k.T_camera_model;
  for (int i = 0; i < s.c.size(); ++i) {
    const Eigen::Vector3d m = s.c.model.col(i);
    const Eigen::Vector2d w = s.c.normalized.col(i);
    const Eigen::Matrix<double, 2, 7> Ai = ImageJacobianQuat(T, m, s.c.fx_px, s.c.fy_px);
    Eigen::Matrix<double, 3, 7> Ao;
    Eigen::Matrix<double, 3, 2> Bo;
    ObjectJacobiansQuat(T, m, w, &Ao, &Bo);
    for (const pose_math::Vector7d& d : TangentDirections(T.q)) {
      const Eigen::Vector2d ni = (ImageResidual(Shift(T, d, kH), m, w, s.c.fx_px, s.c.fy_px) -
                                  ImageResidual(Shift(T, d, -kH), m, w, s.c.fx_px, s.c.fy_px)) /
                                 (2 * kH);
      EXPECT_LT((ni - Ai * d).norm(), 1e-6 * (1.0 + ni.norm()));
      const Eigen::Vector3d no =
          (ObjectResidual(Shift(T, d, kH), m, w) - ObjectResidual(Shift(T, d, -kH), m, w)) / (2 * kH);
      EXPECT_LT((no - Ao * d).norm(), 1e-8);
    }
    for (int k = 0; k < 2; ++k) {  // noise on the normalised image point
      Eigen::Vector2d dw = Eigen::Vector2d::Zero();
      dw(k) = kH;
      const Eigen::Vector3d nb = (ObjectResidual(T, m, w + dw) - ObjectResidual(T, m, w - dw)) / (2 * kH);
      EXPECT_LT((nb - Bo.col(k)).norm(), 1e-8);
    }
  }
}

TEST(CovarianceJacobians, EulerImageAndObjectMatchNumeric) {
  const Fixture s = MakeSetup(21, 6);
  const pose_math::EulerZyx e = pose_math::EulerZyxFromRotation(RotationOf(s.k.T_camera_model));
  const Eigen::Vector3d t = s.k.T_camera_model.t;
  const auto pose_of = [&](const Eigen::Matrix<double, 6, 1>& th) {
    pose_math::EulerZyx ee;
    ee.alpha_rad = th(0), ee.beta_rad = th(1), ee.gamma_rad = th(2);
    return PoseFromRt(pose_math::RotationFromEulerZyx(ee), th.tail<3>());
  };
  Eigen::Matrix<double, 6, 1> th;
  th << e.alpha_rad, e.beta_rad, e.gamma_rad, t;
  for (int i = 0; i < s.c.size(); ++i) {
    const Eigen::Vector3d m = s.c.model.col(i);
    const Eigen::Vector2d w = s.c.normalized.col(i);
    const Eigen::Matrix<double, 2, 6> Ai = ImageJacobianEuler(e, t, m, s.c.fx_px, s.c.fy_px);
    Eigen::Matrix<double, 3, 6> Ao;
    Eigen::Matrix<double, 3, 2> Bo;
    ObjectJacobiansEuler(e, t, m, w, &Ao, &Bo);
    for (int k = 0; k < 6; ++k) {
      Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
      d(k) = kH;
      const Eigen::Vector2d ni = (ImageResidual(pose_of(th + d), m, w, s.c.fx_px, s.c.fy_px) -
                                  ImageResidual(pose_of(th - d), m, w, s.c.fx_px, s.c.fy_px)) /
                                 (2 * kH);
      EXPECT_LT((ni - Ai.col(k)).norm(), 1e-6 * (1.0 + ni.norm()));
      const Eigen::Vector3d no =
          (ObjectResidual(pose_of(th + d), m, w) - ObjectResidual(pose_of(th - d), m, w)) / (2 * kH);
      EXPECT_LT((no - Ao.col(k)).norm(), 1e-8);
    }
  }
}

// Monte Carlo: the same pose and points, fresh image noise each trial, each
// estimator started from the truth (as in 7.1.3). The sample standard
// deviation of N draws has a relative standard error of about 1/sqrt(2(N−1));
// the tolerance is four of those, plus 2% for the first-order approximation.
TEST(CovarianceMonteCarlo, PredictedStandardDeviationsMatchSampled) {
  constexpr int kTrials = 400;
  constexpr double kSigmaPx = 1.0;
  const double tolerance = 4.0 / std::sqrt(2.0 * (kTrials - 1)) + 0.02;
  std::mt19937 rng(22);
  const sim::Case k = sim::RandomCloud(rng, 12);
  const Correspondences truth = ToCorrespondences(k);
  for (const ErrorSpace space : {ErrorSpace::kImage, ErrorSpace::kObject}) {
    const pose_math::Matrix7d cov7 = PoseCovarianceQuat(truth, k.T_camera_model, space, kSigmaPx);
    const Matrix6d cov_euler = PoseCovarianceEuler(truth, k.T_camera_model, space, kSigmaPx);
    const pose_math::EulerZyx e0 = pose_math::EulerZyxFromRotation(RotationOf(k.T_camera_model));
    Eigen::MatrixXd q_samples(kTrials, 7), e_samples(kTrials, 6);
    for (int n = 0; n < kTrials; ++n) {
      const Correspondences c = ToCorrespondences(k, sim::AddNoise(rng, k.image, kSigmaPx));
      const Estimate est = space == ErrorSpace::kImage ? CeresRefine(c, k.T_camera_model, false, 2.0, 50)
                                                       : OrthogonalIteration(c, &k.T_camera_model, 500, 1e-14);
      ASSERT_TRUE(est.ok);
      pose_math::Quat q = est.T_camera_model.q;
      if (q.dot(k.T_camera_model.q) < 0) q = -q;
      q_samples.row(n) << q.transpose(), est.T_camera_model.t.transpose();
      const pose_math::EulerZyx e = pose_math::EulerZyxFromRotation(RotationOf(est.T_camera_model));
      e_samples.row(n) << e.alpha_rad - e0.alpha_rad, e.beta_rad - e0.beta_rad, e.gamma_rad - e0.gamma_rad,
          est.T_camera_model.t.transpose();
    }
    const auto sample_std = [](const Eigen::MatrixXd& s) {
      const Eigen::MatrixXd centred = s.rowwise() - s.colwise().mean();
      return Eigen::VectorXd((centred.array().square().colwise().sum() / (s.rows() - 1)).sqrt());
    };
    const Eigen::VectorXd q_std = sample_std(q_samples), e_std = sample_std(e_samples);
    for (int p = 0; p < 7; ++p) {
      EXPECT_NEAR(std::sqrt(cov7(p, p)) / q_std(p), 1.0, tolerance) << "quaternion parameter " << p;
    }
    for (int p = 0; p < 6; ++p) {
      EXPECT_NEAR(std::sqrt(cov_euler(p, p)) / e_std(p), 1.0, tolerance) << "Euler parameter " << p;
    }
  }
}

TEST(PoseCovariance, RejectsBadSigmaAndRankDeficientGeometry) {
  const Fixture s = MakeSetup(23, 6);
  EXPECT_THROW(PoseCovarianceQuat(s.c, s.k.T_camera_model, ErrorSpace::kImage, 0.0), std::invalid_argument);
  Correspondences two = s.c;
  two.model.conservativeResize(3, 2);
  two.normalized.conservativeResize(2, 2);
  EXPECT_THROW(PoseCovarianceQuat(two, s.k.T_camera_model, ErrorSpace::kImage, 1.0), std::invalid_argument);
  EXPECT_THROW(PoseCovarianceEuler(two, s.k.T_camera_model, ErrorSpace::kImage, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace cone_tracker
