// EkfCore::UpdateCamera: the loosely coupled camera pose update (5.24)-(5.26) and its gate. Update<7> is
// instantiated here (ekf_update.h).
#include <cmath>
#include <limits>

#include "ekf_update.h"
#include "pose_ekf/core/ekf_core.h"
#include "pose_math/covariance.h"

namespace pose_ekf {
namespace {

// The camera covariance lives on the tangent plane of the unit sphere (5.6.4)
// and has no variance along q itself. A tiny radial variance keeps S well
// conditioned; the radial residual is O(angle²) and normalisation (5.41)
// removes whatever it does to the state.
constexpr double kCameraRadialVariance = 1e-10;

// The camera gate's statistic: yᵀ S⁻¹ y for the innovation y and its
// covariance S that the update uses, on the 6 dof a pose has. The quaternion
// rows are taken on the plane tangent to the unit sphere at the prediction
// (the plane R lives on, 5.6.4): along q itself y is only the O(angle²) gap
// between two unit quaternions and S only kCameraRadialVariance, so the 7-dof
// yᵀ S⁻¹ y would grow with the fourth power of a rotation error of a few
// degrees. The statistic does not depend on the basis of the plane. NaN when
// S is not positive definite there.
double CameraGateStatistic(const Eigen::Matrix<double, 7, 1>& y, const Eigen::Matrix<double, 7, 7>& S,
                           const pose_math::Quat& q_pred) {
  Eigen::Matrix<double, 6, 7> T = Eigen::Matrix<double, 6, 7>::Zero();
  T.topLeftCorner<3, 4>() = pose_math::RotationPerturbationToQuat(q_pred).transpose();
  T.bottomRightCorner<3, 3>().setIdentity();
  const Eigen::Matrix<double, 6, 1> y6 = T * y;
  const Eigen::Matrix<double, 6, 6> S6 = T * S * T.transpose();
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(S6);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return y6.dot(ldlt.solve(y6));
}

}  // namespace

UpdateResult EkfCore::UpdateCamera(const CameraMeasurement& m, double* nis, double* gate_chi2) {
  if (!config_.use_camera) return UpdateResult::kDisabled;
  if (!PoseUsable(m)) return UpdateResult::kRejectedNonFinite;
  const int n = static_cast<int>(s_.x.size());
  Eigen::Vector4d z_q = m.T_cones_camera.q.normalized();
  const Eigen::Vector4d q_pred = s_.x.segment<4>(kQ);
  if ((q_pred - z_q).norm() > (q_pred + z_q).norm()) z_q = -z_q;  // mirrored quaternion (5.5.1)
  Eigen::Matrix<double, 7, 1> y;
  y << z_q - q_pred, m.T_cones_camera.t - s_.x.segment<3>(kP);  // z (5.24) - H x (5.25)
  Eigen::Matrix<double, 7, Eigen::Dynamic, 0, 7, kMaxStates> H = Eigen::MatrixXd::Zero(7, n);
  H.block<4, 4>(0, kQ).setIdentity();  // (5.26)
  H.block<3, 3>(4, kP).setIdentity();
  Eigen::Matrix<double, 7, 7> R = m.cov;
  R.topLeftCorner<4, 4>() += kCameraRadialVariance * z_q * z_q.transpose();
  if (gate_chi2 || std::isfinite(camera_gate_chi2_)) {
    Eigen::Matrix<double, 7, 7> S = H * s_.P * H.transpose() + R;  // the S of (5.15)
    S = 0.5 * (S + S.transpose()).eval();
    const double d2 = CameraGateStatistic(y, S, q_pred);
    if (gate_chi2) *gate_chi2 = d2;
    if (std::isfinite(camera_gate_chi2_)) {
      if (std::isnan(d2)) return UpdateResult::kNumericalFailure;
      if (d2 > camera_gate_chi2_) return UpdateResult::kGated;
    }
  }
  return Update<7>(y, H, R, nis);
}

}  // namespace pose_ekf
