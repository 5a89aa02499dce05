// The per-cone camera update (cone_measurement.h) and its gates.
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>

#include <boost/math/distributions/chi_squared.hpp>

#include "pose_ekf/core/cone_measurement.h"
#include "pose_ekf/core/ekf_core.h"
#include "pose_math/quaternion.h"
#include "rig_model/cone_view.h"
#include "rig_model/layout.h"

namespace pose_ekf {
namespace {

using pose_math::Quat;

// R(q)ᵀ v for the general R of (2.36) (Rᵀ(q) = R(q*)) and its derivative w.r.t. q.
// (pose_math::Rotate normalises q; the EKF's h must not, for H to be its exact derivative.)
Eigen::Vector3d RotateInverse(const Quat& q, const Eigen::Vector3d& v) {
  const double q0 = q[0];
  const Eigen::Vector3d qv = -q.tail<3>();
  return (q0 * q0 - qv.squaredNorm()) * v + 2.0 * qv.dot(v) * qv + 2.0 * q0 * qv.cross(v);
}

Eigen::Matrix<double, 3, 4> RotateInverseJacobian(const Quat& q, const Eigen::Vector3d& v) {
  Eigen::Matrix<double, 3, 4> J = pose_math::RotateJacobianWrtQuat(pose_math::Conjugate(q), v);
  J.rightCols<3>() *= -1.0;  // chain rule through q* = diag(1,-1,-1,-1) q
  return J;
}

// ∂(unit horizontal direction from the cone's axis to the camera)/∂p, (3.16) (3.17).
Eigen::Matrix3d TowardJacobian(const Eigen::Vector3d& base_m, const Eigen::Vector3d& p) {
  Eigen::Vector3d w = p - base_m;
  w.z() = 0.0;
  const double n = w.norm();
  if (!(n > 1e-9)) return Eigen::Matrix3d::Zero();  // CorrectedModelPoints' degenerate case: constant
  const Eigen::Vector3d t = w / n;
  Eigen::Matrix3d J = Eigen::Vector3d(1.0, 1.0, 0.0).asDiagonal();
  J -= t * t.transpose();
  return J / n;
}

double Quantile(int dof, double probability) {
  if (!(probability < 1.0)) return std::numeric_limits<double>::infinity();
  return boost::math::quantile(boost::math::chi_squared(dof), probability);
}

}  // namespace

std::vector<ConeGeometry> ConeGeometries(const rig_model::Layout& layout) {
  std::vector<ConeGeometry> out;
  for (const rig_model::ConeSpec& c : layout.cones) out.push_back({c.base_m, c.height_m, c.tau});
  return out;
}

std::string CheckConeFrame(const ConeFrame& f) {
  if (!std::isfinite(f.stamp_s)) return "header.stamp is not finite";
  if (!(f.K.fx_px > 0.0) || !std::isfinite(f.K.fx_px)) return "fx is not positive and finite";
  if (!(f.K.fy_px > 0.0) || !std::isfinite(f.K.fy_px)) return "fy is not positive and finite";
  if (!std::isfinite(f.K.cx_px) || !std::isfinite(f.K.cy_px)) return "cx or cy is not finite";
  static const char* const kNames[kConePoints] = {"peak", "mid", "base"};
  for (size_t i = 0; i < f.cones.size(); ++i) {
    const ConeObservation& o = f.cones[i];
    const std::string at = "cones[" + std::to_string(i) + "].";
    for (int k = 0; k < kConePoints; ++k) {
      if (!o.px[k].allFinite()) return at + kNames[k] + "_px is not finite";
      const Eigen::Matrix2d& c = o.cov_px2[k];
      if (!c.allFinite() || std::abs(c(0, 1) - c(1, 0)) > 1e-9 * (std::abs(c(0, 0)) + std::abs(c(1, 1))) ||
          !(c(0, 0) > 0.0) || !(c.determinant() > 0.0)) {
        return at + kNames[k] + "_cov_px2 is not a finite symmetric positive definite 2x2 matrix";
      }
    }
    if (!o.cone.base_m.allFinite() || !(o.cone.height_m > 0.0) || !(o.cone.tau >= 0.0)) {
      return at + "cone_id " + std::to_string(o.cone_id) + ": layout geometry is not usable";
    }
  }
  return "";
}

bool ProjectCone(const StateVector& x, const ConeGeometry& cone, const PinholeIntrinsics& K, ConeVector* h,
                 ConeJacobian* H) {
  const Quat q = x.segment<4>(kQ);
  const Eigen::Vector3d p = x.segment<3>(kP);
  const auto X_m = rig_model::CorrectedModelPoints(cone.base_m, cone.height_m, cone.tau, p);  // (3.18)
  const double r = cone.tau * cone.height_m;
  const Eigen::Matrix3d dtoward_dp = TowardJacobian(cone.base_m, p);
  // ∂X_m/∂p for peak, mid, base: the surface points follow the camera around the axis.
  const std::array<Eigen::Matrix3d, kConePoints> dX_dp = {Eigen::Matrix3d::Zero(), 0.5 * r * dtoward_dp,
                                                          r * dtoward_dp};
  Eigen::Matrix3d Rt;  // R(q)ᵀ by columns, from the same general form
  for (int i = 0; i < 3; ++i) Rt.col(i) = RotateInverse(q, Eigen::Vector3d::Unit(i));
  if (H) *H = ConeJacobian::Zero(kConeDof, x.size());
  for (size_t j = 0; j < kConeMeasuredPoints.size(); ++j) {
    const int k = kConeMeasuredPoints[j], row = 2 * static_cast<int>(j);
    const Eigen::Vector3d d = X_m[k] - p;
    const Eigen::Vector3d Xc = Rt * d;  // the point in {C}
    if (!(Xc.z() >= kConeMinDepthM)) return false;
    const double iz = 1.0 / Xc.z();
    h->segment<2>(row) << K.fx_px * Xc.x() * iz + K.cx_px, K.fy_px * Xc.y() * iz + K.cy_px;  // pinhole
    if (!H) continue;
    Eigen::Matrix<double, 2, 3> dpi;  // ∂(u, v)/∂Xc
    dpi << K.fx_px * iz, 0.0, -K.fx_px * Xc.x() * iz * iz, 0.0, K.fy_px * iz, -K.fy_px * Xc.y() * iz * iz;
    H->block<2, 4>(row, kQ) = dpi * RotateInverseJacobian(q, d);
    H->block<2, 3>(row, kP) = dpi * Rt * (dX_dp[k] - Eigen::Matrix3d::Identity());
  }
  return true;
}

ConeMatrix ConeCovariance(const ConeObservation& o) {
  ConeMatrix R = ConeMatrix::Zero();
  for (size_t j = 0; j < kConeMeasuredPoints.size(); ++j) {
    const Eigen::Matrix2d& c = o.cov_px2[kConeMeasuredPoints[j]];
    R.block<2, 2>(2 * j, 2 * j) = 0.5 * (c + c.transpose());
  }
  return R;
}

ConeVector ConePixels(const ConeObservation& o) {
  ConeVector z;
  for (size_t j = 0; j < kConeMeasuredPoints.size(); ++j) z.segment<2>(2 * j) = o.px[kConeMeasuredPoints[j]];
  return z;
}

// Gauss-Newton on J (the iterated EKF update's steps): linearised at x, the minimiser of the prior term
// plus the linearised pixel term is x0 + P Hᵀ S⁻¹ (z - h - H (x0 - x)). Every iterate is x0 + P a, so the
// prior term is aᵀ P a, with no inverse of P (whose quaternion block is nearly singular).
double ConeFitCost(const StateVector& x0, const StateMatrix& P, const ConeGeometry& cone, const PinholeIntrinsics& K,
                   const ConeVector& z, const ConeMatrix& R, int iterations, StateVector* x_fit) {
  // h reads q and p only, so H and a = Hᵀ w live on those 7 states: the steps are 7-dimensional.
  constexpr int kN = 7;
  using Vec = Eigen::Matrix<double, kN, 1>;
  const std::array<int, kN> idx = {kQ, kQ + 1, kQ + 2, kQ + 3, kP, kP + 1, kP + 2};
  Eigen::Matrix<double, kN, kN> P7;
  for (int r = 0; r < kN; ++r)
    for (int c = 0; c < kN; ++c) P7(r, c) = P(idx[r], idx[c]);
  const double kInf = std::numeric_limits<double>::infinity();
  const Eigen::LDLT<ConeMatrix> R_ldlt(R);
  StateVector x = x0;  // x0 + P a on q and p; the other states do not enter h
  const auto at = [&](const Vec& a) -> const StateVector& {
    const Vec d = P7 * a;
    for (int r = 0; r < kN; ++r) x[idx[r]] = x0[idx[r]] + d[r];
    return x;
  };
  ConeVector h;
  ConeJacobian H;
  const auto cost = [&](const Vec& a) {  // J at x0 + P a
    if (!ProjectCone(at(a), cone, K, &h, nullptr)) return kInf;
    const ConeVector r = z - h;
    return a.dot(P7 * a) + r.dot(R_ldlt.solve(r));
  };
  Vec a = Vec::Zero();
  if (x_fit) *x_fit = x0;
  double J = cost(a);
  if (!std::isfinite(J)) return kInf;
  for (int it = 0; it < std::max(iterations, 1); ++it) {
    if (!ProjectCone(at(a), cone, K, &h, &H)) break;
    Eigen::Matrix<double, kConeDof, kN> H7;
    for (int c = 0; c < kN; ++c) H7.col(c) = H.col(idx[c]);
    ConeMatrix S = H7 * P7 * H7.transpose() + R;
    S = 0.5 * (S + S.transpose()).eval();
    const Eigen::LDLT<ConeMatrix> ldlt(S);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) break;
    const ConeVector y = z - h + H7 * (P7 * a);
    const ConeVector w = ldlt.solve(y);
    if (iterations == 0) return y.dot(w);  // first order: yᵀ S⁻¹ y at x0
    const Vec step = H7.transpose() * w - a;
    double lambda = 1.0, J_new = cost(a + step);
    for (int halving = 0; halving < 6 && !(J_new < J); ++halving) {
      lambda *= 0.5;
      J_new = cost(a + lambda * step);
    }
    if (!(J_new < J)) break;
    a += lambda * step;
    // Converged when the cost stops falling, or when the full step reached the linearised minimum yᵀ S⁻¹ y (h
    // linear over the step: the next linearisation gives the same point; the tracked case, in one step).
    const double tolerance = 1e-3 * (1.0 + J_new);
    const bool converged = J - J_new < tolerance || (lambda == 1.0 && std::abs(J_new - y.dot(w)) < tolerance);
    J = J_new;
    if (converged) break;
  }
  if (x_fit) *x_fit = at(a);
  return J;
}

namespace {

// Every layout cone's silhouette at x (nullopt: not projected), from the projected peak and base, tau times their
// distance wide.
std::vector<std::optional<rig_model::ConeSilhouette>> SilhouettesAt(const StateVector& x, const ConeFrame& f) {
  std::vector<std::optional<rig_model::ConeSilhouette>> silhouettes(f.layout.size());
  ConeVector h;
  for (size_t k = 0; k < f.layout.size(); ++k) {
    if (!ProjectCone(x, f.layout[k], f.K, &h, nullptr)) continue;
    const Eigen::Vector2d peak = h.segment<2>(0), base = h.segment<2>(2);
    silhouettes[k] = rig_model::ConeSilhouette{peak, base, f.layout[k].tau * (peak - base).norm()};
  }
  return silhouettes;
}

using Silhouettes = std::vector<std::optional<rig_model::ConeSilhouette>>;

int MissedIn(const Silhouettes& silhouettes, const ConeFrame& f, const std::vector<int>& seen) {
  if (!(f.width_px > 0.0 && f.height_px > 0.0)) return 0;
  std::vector<bool> seen_k(f.layout.size(), false);
  for (int id : seen)
    if (id >= 0 && static_cast<size_t>(id) < seen_k.size()) seen_k[static_cast<size_t>(id)] = true;
  return rig_model::MissedInView(silhouettes, seen_k, f.orange_px, f.width_px, f.height_px);
}

int UnexplainedIn(const Silhouettes& silhouettes, const ConeFrame& f) {
  if (f.orange_px.empty()) return 0;
  std::vector<rig_model::ConeSilhouette> detected;
  for (const ConeObservation& o : f.cones) detected.push_back(rig_model::DetectedSilhouette(o.px[0], o.px[2]));
  return rig_model::UnexplainedOrange(silhouettes, detected, f.orange_px, f.width_px, f.height_px);
}

}  // namespace

int ConesMissedAt(const StateVector& x, const ConeFrame& f, const std::vector<int>& seen) {
  return MissedIn(SilhouettesAt(x, f), f, seen);
}

int OrangeUnexplainedAt(const StateVector& x, const ConeFrame& f) { return UnexplainedIn(SilhouettesAt(x, f), f); }

// The iterated EKF update of one cone: the update from the prior x0 linearised at x_i takes the residual
// z - h(x_i) - H_i (x0 - x_i) (x_i = x0 first: the EKF's (5.15)-(5.17)); each pass starts from the prior
// again, and the covariance is the last linearisation's. *nis is the first pass's: at the state this cone
// starts from (the previous cones'), the statistic the frame's joint check sums.
UpdateResult EkfCore::UpdateCone(const ConeObservation& o, const PinholeIntrinsics& K, double* nis) {
  constexpr double kConvergedPx = 0.1;
  const FilterState prior = s_;
  const ConeVector z = ConePixels(o);
  const ConeMatrix R = ConeCovariance(o);
  StateVector x_lin = prior.x;
  ConeVector h, h_new;
  ConeJacobian H;
  FilterState last;  // the previous pass's update, kept when a later pass fails
  for (int pass = 0; pass <= config_.cone_update_iterations; ++pass) {
    if (!ProjectCone(x_lin, o.cone, K, &h, &H)) break;
    const ConeVector y = z - h - H * (prior.x - x_lin);
    if (pass > 0) s_ = prior;  // the first pass starts there already
    if (Update<kConeDof>(y, H, R, pass == 0 ? nis : nullptr) != UpdateResult::kApplied) {
      s_ = pass == 0 ? prior : last;
      return pass == 0 ? UpdateResult::kNumericalFailure : UpdateResult::kApplied;
    }
    // Linear enough over the step: the updated state predicts the pixels the linearisation did.
    if (pass == config_.cone_update_iterations || !ProjectCone(s_.x, o.cone, K, &h_new, nullptr) ||
        (h_new - h - H * (s_.x - x_lin)).cwiseAbs().maxCoeff() < kConvergedPx)
      return UpdateResult::kApplied;
    last = s_;
    x_lin = s_.x;
  }
  s_ = prior;
  return UpdateResult::kNumericalFailure;
}

// A lower bound on every J(x) of ConeFitCost, valid for the prior terms up to t2. Write x = x0 + δ with prior term s² =
// δᵀ P⁺ δ (the iterates x0 + P a: δ = P a, s² = aᵀ P a). Then |δq| ≤ kq s and |δp| ≤ kp s, kq² and kp² being at least
// the largest eigenvalues of P's q and p blocks. A model point's direction in {C}, R(q)ᵀ (X - p) (R(q) = |q|² times the
// rotation of q/|q|, (2.36)), turns from its direction at x0 by at most the rotation between q and q0, ≤ 2 asin(|δq| /
// |q0|) (the widest angle of a ball of radius |δq| about q0 seen from 0; a rotation's angle is twice its quaternion's),
// plus asin((|δp| + e) / |X0 - p0|) for the point's own move e: 0 for the peak, r = τ h for the base, which stays on
// its circle about the axis (3.18). So the point is at least (its angle A0 from the observed pixel's ray at x0) - (that
// turn) = gap(s) off that ray. The pinhole maps rays in front of the camera to pixels at least min(fx, fy) times their
// angle apart (the gnomonic map stretches every direction by ≥ 1, and the segment is the image of the arc), and R is
// block-diagonal, so the pixel term is at least G(s) = min(fx, fy)² (gap_peak² + gap_base²) / λmax(R). G falls with s:
// for s² ≥ t2, J ≥ t2; for s² < t2, J ≥ G(√t2). Hence J ≥ min(t2, G(√t2)) at every x (a point behind the camera costs
// infinity), and so is every cost ConeFitCost returns, which is J at an iterate.
double ConeFitLowerBound(const StateVector& x0, const StateMatrix& P, const ConeGeometry& cone,
                         const PinholeIntrinsics& K, const ConeVector& z, const ConeMatrix& R, double t2) {
  static_assert(kConeMeasuredPoints[0] == 0 && kConeMeasuredPoints[1] == 2, "z and R: the peak, then the base");
  if (!(t2 > 0.0)) return 0.0;
  const Quat q0 = x0.segment<4>(kQ);
  const Eigen::Vector3d p0 = x0.segment<3>(kP);
  const double s = std::sqrt(t2);
  // λmax ≤ ‖A‖₂ ≤ both the Frobenius norm and the largest absolute row sum (A symmetric).
  const auto lambda_bound = [](const auto& A) { return std::min(A.norm(), A.cwiseAbs().rowwise().sum().maxCoeff()); };
  const double rq = std::sqrt(lambda_bound(P.block<4, 4>(kQ, kQ))) * s / q0.norm();
  if (!(rq < 1.0)) return 0.0;  // a turn that can point anywhere
  const double turn = 2.0 * std::asin(rq), shift = std::sqrt(lambda_bound(P.block<3, 3>(kP, kP))) * s;
  const auto gap = [&](int row, const Eigen::Vector3d& X0, double e) {  // ≥ 0 radians
    const Eigen::Vector3d ray(z[row] - K.cx_px, (z[row + 1] - K.cy_px) * K.fx_px / K.fy_px, K.fx_px);
    const Eigen::Vector3d d0 = RotateInverse(q0, X0 - p0);
    const double ratio = (shift + e) / (X0 - p0).norm();
    if (!(ratio < 1.0)) return 0.0;
    return std::max(0.0, std::atan2(ray.cross(d0).norm(), ray.dot(d0)) - turn - std::asin(ratio));
  };
  const double r = cone.tau * cone.height_m;
  const double g_peak = gap(0, cone.base_m + Eigen::Vector3d(0.0, 0.0, cone.height_m), 0.0);
  const double g_base = gap(2, cone.base_m, r);
  // λmax(R): the larger of its 2x2 blocks' (ConeCovariance is block-diagonal), else its Frobenius norm.
  const auto lambda2 = [&](int i) {
    const double a = R(i, i), c = R(i + 1, i + 1), b = 0.5 * (R(i, i + 1) + R(i + 1, i));
    return 0.5 * (a + c) + std::sqrt(0.25 * (a - c) * (a - c) + b * b);
  };
  const double lambda_max = R.topRightCorner<2, 2>().isZero(0.0) && R.bottomLeftCorner<2, 2>().isZero(0.0)
                                ? std::max(lambda2(0), lambda2(2))
                                : R.norm();
  const double f = std::min(K.fx_px, K.fy_px);
  return std::min(t2, f * f * (g_peak * g_peak + g_base * g_base) / lambda_max);
}

void EkfCore::SetConeGates() {
  cone_gate_chi2_ = Quantile(kConeDof, config_.cone_gate_probability);
  cone_joint_chi2_.clear();
  for (int k = 1; k <= kConeJointTableSize; ++k)
    cone_joint_chi2_.push_back(Quantile(k * kConeDof, config_.cone_joint_probability));
}

double EkfCore::cone_joint_chi2(int cones) const {
  if (cones < 1) return 0.0;
  if (cones <= static_cast<int>(cone_joint_chi2_.size())) return cone_joint_chi2_[static_cast<size_t>(cones - 1)];
  return Quantile(cones * kConeDof, config_.cone_joint_probability);
}

// Sequential per cone: with the cones' pixel noise independent (R block-diagonal across cones), the
// sequential updates equal the joint one for a linear h, each a 4×4 S instead of a 4k×4k one, and
// every cone is linearised at the state the previous cones corrected. The joint NIS of the frame is
// the sum of the sequential NIS values (p(z1, z2) = p(z1) p(z2 | z1)), so the frame check costs
// nothing extra; it needs a rollback, hence the copy of the state.
UpdateResult EkfCore::UpdateCones(const ConeFrame& f, ConeFrameResult* out, int min_cones) {
  ConeFrameResult res;
  if (!config_.use_camera) return UpdateResult::kDisabled;
  if (!initialized_ || f.cones.empty()) return UpdateResult::kDisabled;
  if (!CheckConeFrame(f).empty()) return UpdateResult::kRejectedNonFinite;
  // 0. The same view as the last fused frame: the same pixel errors again, not fused; what it does tell is that the
  // camera has not moved (README, "Repeated views").
  if (config_.cone_repeat_px > 0.0 &&
      RepeatsView(s_.fused_view, f, config_.cone_repeat_px, config_.cone_repeat_max_s)) {
    res.repeated = true;
    UpdateStill(config_.cone_repeat_sigma_v_m_s, config_.cone_repeat_sigma_omega_rad_s);
    if (out) *out = res;
    return UpdateResult::kDisabled;
  }
  const FilterState prior = s_;
  // 1. Per cone against the prior: the image-space gate of 6.4.1, on the filter's own S.
  std::vector<int> candidates;
  std::vector<double> d2(f.cones.size(), 0.0);
  std::vector<bool> by_fit(f.cones.size(), false);  // judged by the fit, not the first-order statistic
  ConeVector h;
  ConeJacobian H;
  for (size_t i = 0; i < f.cones.size(); ++i) {
    const ConeObservation& o = f.cones[i];
    if (!ProjectCone(s_.x, o.cone, f.K, &h, &H)) {
      ++res.behind_camera;
      continue;
    }
    const ConeVector y = ConePixels(o) - h;
    ConeMatrix S = H * s_.P * H.transpose() + ConeCovariance(o);  // the S of (5.15)
    S = 0.5 * (S + S.transpose()).eval();
    const Eigen::LDLT<ConeMatrix> ldlt(S);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) {
      ++res.numerical;
      continue;
    }
    d2[i] = y.dot(ldlt.solve(y));
    // After a long outage the prior is decimetres off, and yᵀ S⁻¹ y, first order at it, also counts the
    // projection's curvature over that shift: a cone beyond the gate at first order is judged by its fit
    // instead (ConeFitCost, the iterated update's cost on the prior; README, "Re-acquisition").
    if (d2[i] > cone_gate_chi2_ && config_.cone_ambiguity_iterations > 0) {
      d2[i] = ConeFitCost(prior.x, prior.P, o.cone, f.K, ConePixels(o), ConeCovariance(o),
                          config_.cone_ambiguity_iterations);
      by_fit[i] = true;
    }
    res.worst_gate_chi2 = std::max(res.worst_gate_chi2, d2[i]);
    if (d2[i] > cone_gate_chi2_) {
      ++res.gated;
      continue;
    }
    candidates.push_back(static_cast<int>(i));
  }
  // 1b. A cone fused alone (the frame's only cone, or the only one its gates left) whose pixels another
  // layout cone explains nearly as well (its fit within cone_ambiguity_margin of the named cone's,
  // ConeFitCost on the prior) is not fused: with the position sigma of a long outage one detection may
  // be any cone (README, "Re-acquisition").
  const auto ambiguous_alone = [&](int i) {
    const ConeObservation& o = f.cones[static_cast<size_t>(i)];
    const ConeVector z = ConePixels(o);
    const ConeMatrix Rn = ConeCovariance(o);
    const int iterations = config_.cone_ambiguity_iterations;
    // Negative information (iterated fits only: first order has no fitted pose): each reading also pays for the
    // layout cones its pose puts in plain view that the frame does not have (its other cones were seen, whatever
    // they are).
    const bool negative = iterations > 0 && config_.cone_miss_cost > 0.0 && f.width_px > 0.0 && f.height_px > 0.0;
    const bool clutter = iterations > 0 && config_.cone_unexplained_cost > 0.0;
    std::vector<int> seen;
    for (size_t k = 0; k < f.cones.size(); ++k)
      if (static_cast<int>(k) != i) seen.push_back(f.cones[k].cone_id);
    // A reading's misses and the orange it leaves over, from the layout projected once at its fitted pose.
    const auto evidence = [&](const StateVector& x, int as_cone, int* missed, int* unexplained) {
      *missed = *unexplained = 0;
      if (!negative && !clutter) return 0.0;
      const Silhouettes silhouettes = SilhouettesAt(x, f);
      if (negative) {
        seen.push_back(as_cone);
        *missed = MissedIn(silhouettes, f, seen);
        seen.pop_back();
      }
      if (clutter) *unexplained = UnexplainedIn(silhouettes, f);
      return config_.cone_miss_cost * *missed + config_.cone_unexplained_cost * *unexplained;
    };
    StateVector x_fit;
    res.ambiguity_own_chi2 = iterations > 0 ? ConeFitCost(prior.x, prior.P, o.cone, f.K, z, Rn, iterations, &x_fit)
                                            : d2[static_cast<size_t>(i)];
    res.ambiguity_own_chi2 += evidence(x_fit, o.cone_id, &res.ambiguity_own_missed, &res.ambiguity_own_unexplained);
    res.ambiguity_rival_chi2 = std::numeric_limits<double>::infinity();
    res.ambiguity_screened = 0;
    // A rival whose every fit costs more than own + margin (ConeFitLowerBound; sound for the iterated fit only,
    // whose result is J at an iterate) cannot make the cone ambiguous: it is not fitted. (1 + 1e-9: rounding.)
    const double beyond = (res.ambiguity_own_chi2 + config_.cone_ambiguity_margin) * (1.0 + 1e-9);
    for (size_t j = 0; j < f.layout.size(); ++j) {
      if (static_cast<int>(j) == o.cone_id) continue;
      if (iterations > 0 && ConeFitLowerBound(prior.x, prior.P, f.layout[j], f.K, z, Rn, beyond) >= beyond) {
        ++res.ambiguity_screened;
        continue;
      }
      int rival_missed = 0, rival_unexplained = 0;
      double rival = ConeFitCost(prior.x, prior.P, f.layout[j], f.K, z, Rn, iterations, &x_fit);
      rival += evidence(x_fit, static_cast<int>(j), &rival_missed, &rival_unexplained);  // at the fit just made
      if (rival < res.ambiguity_rival_chi2) {
        res.ambiguity_rival_chi2 = rival;
        res.ambiguity_rival_id = static_cast<int>(j);
        res.ambiguity_rival_missed = rival_missed;
        res.ambiguity_rival_unexplained = rival_unexplained;
      }
    }
    return res.ambiguity_rival_chi2 - res.ambiguity_own_chi2 < config_.cone_ambiguity_margin;
  };
  // Re-acquiring, the best-fitting cone goes first, so a cone the prior reaches only at first order
  // is linearised at the state the other one corrected.
  if (min_cones > 1)
    std::stable_sort(candidates.begin(), candidates.end(),
                     [&](int a, int b) { return d2[static_cast<size_t>(a)] < d2[static_cast<size_t>(b)]; });
  // 2. The remaining cones in sequence; the frame's joint NIS against chi2(4 k), else drop the
  // cone that disagreed most with the prior and try again (a wrong association that passed alone).
  UpdateResult result = UpdateResult::kGated;
  while (!candidates.empty()) {
    if (static_cast<int>(candidates.size()) < min_cones) {
      res.too_few = static_cast<int>(candidates.size());  // re-acquiring: no fewer than min_cones together
      break;
    }
    if (candidates.size() == 1 && config_.cone_ambiguity_margin > 0.0 && ambiguous_alone(candidates[0])) {
      res.ambiguous = 1;
      break;
    }
    s_ = prior;
    double nis_sum = 0.0;
    int failed = -1;
    for (int i : candidates) {
      const ConeObservation& o = f.cones[static_cast<size_t>(i)];
      // A cone judged by its fit at its gate adds its fit's statistic, from where its update starts (the previous
      // cones' correction), to the frame's: the first-order one would count the curvature again.
      std::optional<FilterState> from;
      if (by_fit[static_cast<size_t>(i)]) from = s_;
      double nis = 0.0;
      if (UpdateCone(o, f.K, &nis) != UpdateResult::kApplied) {
        failed = i;
        break;
      }
      if (from)
        nis = std::min(nis, ConeFitCost(from->x, from->P, o.cone, f.K, ConePixels(o), ConeCovariance(o),
                                        config_.cone_ambiguity_iterations));
      nis_sum += nis;
    }
    const int k = static_cast<int>(candidates.size());
    if (failed >= 0) {
      ++res.numerical;
      candidates.erase(std::find(candidates.begin(), candidates.end(), failed));
      continue;
    }
    res.joint_threshold = cone_joint_chi2(k);
    if (nis_sum <= res.joint_threshold) {
      res.fused = k;
      res.nis = nis_sum;
      NoteFusedView(f, candidates, &s_.fused_view);
      result = UpdateResult::kApplied;
      break;
    }
    const auto worst = std::max_element(candidates.begin(), candidates.end(), [&](int a, int b) {
      return d2[static_cast<size_t>(a)] < d2[static_cast<size_t>(b)];
    });
    candidates.erase(worst);
    ++res.joint_dropped;
  }
  if (result != UpdateResult::kApplied) {
    s_ = prior;
    // A cone the prediction puts behind the camera disagrees with it, like a gated one.
    if (res.gated + res.joint_dropped + res.behind_camera + res.too_few + res.ambiguous == 0)
      result = UpdateResult::kNumericalFailure;
  }
  if (out) *out = res;
  return result;
}

}  // namespace pose_ekf
