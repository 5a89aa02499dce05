// EkfCore::Update<M>, the measurement update every sensor shares ((5.15) (5.16) (5.17)), for the sources that
// instantiate it, one each: ekf_camera_update.cpp (M = 7), ekf_imu_update.cpp (M = 3) and
// ekf_cone_update.cpp (M = kConeDof). Each instantiation is most of a minute of the compiler's time at -O3;
// in separate sources they build in parallel (.ci/README.md). Private to src/core.
#pragma once

#include <Eigen/Cholesky>

#include "pose_ekf/core/ekf_core.h"
#include "pose_math/covariance.h"

namespace pose_ekf {

inline void NormalizeQuat(StateVector& x) { x.segment<4>(kQ).normalize(); }  // (5.41)

template <int M>
UpdateResult EkfCore::Update(const Eigen::Matrix<double, M, 1>& residual,
                             const Eigen::Matrix<double, M, Eigen::Dynamic, 0, M, kMaxStates>& H,
                             const Eigen::Matrix<double, M, M>& R, double* nis) {
  using MatNM = Eigen::Matrix<double, Eigen::Dynamic, M, 0, kMaxStates, M>;
  const int n = static_cast<int>(s_.x.size());
  const MatNM PHt = s_.P * H.transpose();
  Eigen::Matrix<double, M, M> S = H * PHt + R;
  S = 0.5 * (S + S.transpose()).eval();
  const Eigen::LDLT<Eigen::Matrix<double, M, M>> ldlt(S);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || !(ldlt.vectorD().minCoeff() > 0.0)) {
    return UpdateResult::kNumericalFailure;
  }
  const MatNM K = ldlt.solve(PHt.transpose()).transpose();  // (5.15)
  StateVector x = s_.x + K * residual;                      // (5.16)
  StateMatrix P(n, n);
  if (config_.joseph_update) {
    StateMatrix IKH = StateMatrix::Identity(n, n) - K * H;
    P = IKH * s_.P * IKH.transpose() + K * R * K.transpose();  // Joseph form of (5.17)
  } else {
    P = s_.P - K * PHt.transpose();  // (I - K H) P (5.17), with H P = (P Hᵀ)ᵀ
  }
  pose_math::SymmetrizeCovariance(P);
  NormalizeQuat(x);  // (5.41)
  if (!x.allFinite() || !P.allFinite()) return UpdateResult::kNumericalFailure;
  if (nis) *nis = residual.dot(ldlt.solve(residual));
  s_.x = x;
  s_.P = P;
  return UpdateResult::kApplied;
}

}  // namespace pose_ekf
