#include "cone_tracker/pose/associate.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include <Eigen/Cholesky>
#include <boost/math/distributions/chi_squared.hpp>

#include "pose_math/rotation.h"

namespace cone_tracker {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// A point in camera coordinates to pinhole pixels (the association works on undistorted points).
Eigen::Vector2d Pinhole(const CameraModel& cam, const Eigen::Vector3d& p) {
  return {cam.fx_px * p.x() / p.z() + cam.cx_px, cam.fy_px * p.y() / p.z() + cam.cy_px};
}

// Projects a cone's three points; false when one is too near or behind the
// camera, or far outside the image. The Jacobian is against a small rotation
// of the camera (R' = Exp(dtheta) R, in the camera frame) and a shift of its
// position in `cones`: p_camera = R (p - c) moves by dtheta x p_camera - R dc.
bool ProjectCone(const ConePoints3d& pts, const Eigen::Matrix3d& R, const Eigen::Vector3d& eye, const CameraModel& cam,
                 const AssociationConfig& cfg, ConeCandidate* out, double extra_px = 0.0) {
  const double mu = cfg.outside_frac * cam.width_px + extra_px, mv = cfg.outside_frac * cam.height_px + extra_px;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d p = R * (pts[size_t(i)] - eye);
    if (!(p.z() > cfg.min_depth_m)) return false;
    const Eigen::Vector2d uv = Pinhole(cam, p);
    const double u = uv.x(), v = uv.y();
    if (u < -mu || v < -mv || u > cam.width_px - 1 + mu || v > cam.height_px - 1 + mv) return false;
    Eigen::Matrix<double, 2, 3> duv_dp;
    duv_dp << cam.fx_px / p.z(), 0, -cam.fx_px * p.x() / (p.z() * p.z()), 0, cam.fy_px / p.z(),
        -cam.fy_px * p.y() / (p.z() * p.z());
    out->predicted_px.segment<2>(2 * i) << u, v;
    out->jacobian.block<2, 3>(2 * i, 0) = duv_dp * -Skew(p);
    out->jacobian.block<2, 3>(2 * i, 3) = duv_dp * -R;
  }
  return true;
}

// exp of the skew matrix of v: the rotation by |v| about v (R' = Exp(dtheta) R above).
Eigen::Matrix3d Exp(const Eigen::Vector3d& v) {
  return pose_math::RotationFromQuat(pose_math::QuatFromRotationVector(v));
}

// A layout cone's silhouette in the image: the base point is the base radius off the axis (3.18), its horizontal
// offset from the peak the half-width.
rig_model::ConeSilhouette Silhouette(const ConePoints3d& p, const Eigen::Vector2d& peak_px,
                                     const Eigen::Vector2d& base_px, double base_depth_m, const CameraModel& cam) {
  return {peak_px, base_px, cam.fx_px * (p[2] - p[0]).head<2>().norm() / base_depth_m};
}

Vector6d Stack(const ConePoints2d& d) {
  Vector6d v;
  v << d[0], d[1], d[2];
  return v;
}

}  // namespace

std::vector<std::optional<rig_model::ConeSilhouette>> LayoutSilhouettes(const ModelPointsAt& model, size_t num_cones,
                                                                        const Eigen::Matrix3d& R_camera_cones,
                                                                        const Eigen::Vector3d& eye,
                                                                        const CameraModel& cam, double min_depth_m) {
  std::vector<std::optional<rig_model::ConeSilhouette>> silhouettes(num_cones);
  for (size_t k = 0; k < num_cones; ++k) {
    const ConePoints3d p = model(k, eye);
    const Eigen::Vector3d peak = R_camera_cones * (p[0] - eye), base = R_camera_cones * (p[2] - eye);
    if (!(peak.z() > min_depth_m && base.z() > min_depth_m)) continue;
    silhouettes[k] = Silhouette(p, Pinhole(cam, peak), Pinhole(cam, base), base.z(), cam);
  }
  return silhouettes;
}

std::string AssociationConfig::Validate() const {
  if (!(sigma_px > 0.0)) return "sigma_px must be > 0";
  if (!(prediction_sigma_m > 0.0)) return "prediction_sigma_m must be > 0";
  if (!(prediction_sigma_rad > 0.0)) return "prediction_sigma_rad must be > 0";
  if (!(gate_probability > 0.0 && gate_probability < 1.0)) return "gate_probability must be in (0, 1)";
  if (!(ambiguity_margin >= 0.0)) return "ambiguity_margin must be >= 0";
  if (!(outside_frac >= 0.0)) return "outside_frac must be >= 0";
  if (!(min_depth_m > 0.0)) return "min_depth_m must be > 0";
  if (!(overlap_sigmas >= 0.0)) return "overlap_sigmas must be >= 0";
  if (!(unexplained_cost >= 0.0)) return "unexplained_cost must be >= 0";
  if (!(miss_cost >= 0.0)) return "miss_cost must be >= 0";
  if (!(plain_view.margin_px >= 0.0 && plain_view.min_height_px >= 0.0))
    return "plain_view margin_px and min_height_px must be >= 0";
  return "";
}

Matrix6d AssociationPrior(const pose_math::Quat& q_cones_camera, const Matrix6d& cov_ros) {
  // R_camera_cones' = (Exp(dtheta) R_cones_camera)' = Exp(-R_camera_cones dtheta) R_camera_cones.
  const Eigen::Matrix3d R_camera_cones = pose_math::RotationFromQuat(q_cones_camera).transpose();
  Matrix6d A = Matrix6d::Zero();  // (rotation in the camera frame, position) from (position, rotation in cones)
  A.block<3, 3>(0, 3) = -R_camera_cones;
  A.block<3, 3>(3, 0) = Eigen::Matrix3d::Identity();
  const Matrix6d P = A * cov_ros * A.transpose();
  return 0.5 * (P + P.transpose());
}

std::array<Eigen::Matrix2d, 3> PointCovariances(const ConePoints2d& pts, double area_px, double sigma_px) {
  const Eigen::Matrix2d iso = sigma_px * sigma_px * Eigen::Matrix2d::Identity();
  std::array<Eigen::Matrix2d, 3> cov{iso, iso, iso};
  const Eigen::Vector2d axis = pts[0] - pts[2];
  const double h = axis.norm();
  if (h > 1e-6 && area_px > 0.0) {
    const double tip_px = std::min(h * h / (2.0 * area_px), 0.5 * h);  // h / w, w = 2 area / h
    const Eigen::Vector2d a = axis / h;
    const Eigen::Matrix2d along = a * a.transpose();  // exactly symmetric
    cov[0] += (tip_px * tip_px / 12.0) * along;       // uniform over the sub-pixel tip
  }
  return cov;
}

AssociationResult AssociateCones(const std::vector<ConePoints2d>& dets,
                                 const std::vector<std::array<Eigen::Matrix2d, 3>>& point_cov, size_t num_cones,
                                 const ModelPointsAt& model, const CameraModel& cam, const pose_math::Pose& T_pred,
                                 const AssociationConfig& cfg, const std::vector<rig_model::ImageBox>& orange) {
  AssociationResult out;
  const size_t nd = dets.size();
  out.cone_of_detection.assign(nd, -1);
  out.d2.assign(nd, std::numeric_limits<double>::quiet_NaN());
  const Eigen::Matrix3d R = pose_math::RotationFromQuat(T_pred.q);
  const Eigen::Vector3d eye = -(R.transpose() * T_pred.t);
  Matrix6d prior = Matrix6d::Zero();
  if (cfg.prediction_cov) {
    prior = 0.5 * (*cfg.prediction_cov + cfg.prediction_cov->transpose());
  } else {
    prior.diagonal() << Eigen::Vector3d::Constant(cfg.prediction_sigma_rad * cfg.prediction_sigma_rad),
        Eigen::Vector3d::Constant(cfg.prediction_sigma_m * cfg.prediction_sigma_m);
  }
  std::vector<rig_model::ImageBox> boxes;  // predicted silhouettes
  for (size_t c = 0; c < num_cones; ++c) {
    ConeCandidate k;
    k.cone = int(c);
    const ConePoints3d p = model(c, eye);
    if (!ProjectCone(p, R, eye, cam, cfg, &k)) continue;
    out.candidates.push_back(k);
    boxes.push_back(
        Silhouette(p, k.predicted_px.head<2>(), k.predicted_px.tail<2>(), (R * (p[2] - eye)).z(), cam).Box());
  }
  // Cones predicted to overlap in the image are left out: the segmentation
  // merges them into one blob or cuts the far one, whose points fit neither.
  // Only an overlap the prediction is sure of: deeper, both across and along the
  // image, than overlap_sigmas standard deviations of the two cones' predicted
  // offset from each other (their base points' Jacobians under the prior). After
  // an outage the prior's metre can part two cones predicted on top of each other
  // (look_away at 256x192, 12.9-13.2 s: cones 0 and 1 predicted overlapping by
  // 21 px, their offset's sigma 91 px, seen 85 px apart: nothing was associated
  // until a third cone came). The cones of an overlap it is not sure of stay
  // candidates but are no evidence of a conflict (below): a blob there may be
  // their merged silhouette.
  std::vector<bool> overlaps(out.candidates.size(), false), maybe_merged(out.candidates.size(), false);
  for (size_t i = 0; i < boxes.size(); ++i)
    for (size_t j = i + 1; j < boxes.size(); ++j) {
      const double du = std::min(boxes[i].u_max, boxes[j].u_max) - std::max(boxes[i].u_min, boxes[j].u_min);
      const double dv = std::min(boxes[i].v_max, boxes[j].v_max) - std::max(boxes[i].v_min, boxes[j].v_min);
      if (!(du > 0.0 && dv > 0.0)) continue;
      const Eigen::Matrix<double, 2, 6> J_apart =
          out.candidates[i].jacobian.bottomRows<2>() - out.candidates[j].jacobian.bottomRows<2>();
      const Eigen::Matrix2d S = J_apart * prior * J_apart.transpose();
      if (du > cfg.overlap_sigmas * std::sqrt(S(0, 0)) && dv > cfg.overlap_sigmas * std::sqrt(S(1, 1)))
        overlaps[i] = overlaps[j] = true;
      else
        maybe_merged[i] = maybe_merged[j] = true;
    }
  std::vector<ConeCandidate> apart;
  std::vector<bool> apart_maybe_merged;
  for (size_t i = 0; i < overlaps.size(); ++i) {
    if (overlaps[i]) {
      out.overlapping.push_back(out.candidates[i].cone);
    } else {
      apart.push_back(out.candidates[i]);
      apart_maybe_merged.push_back(maybe_merged[i]);
    }
  }
  out.candidates = apart;
  const size_t nc = out.candidates.size();
  const double gate = boost::math::quantile(boost::math::chi_squared(4), cfg.gate_probability);  // peak, base
  out.cost = gate * double(nd);
  if (nc == 0 || nd == 0) return out;
  const Eigen::LDLT<Matrix6d> prior_ldlt(prior);
  if (prior_ldlt.info() != Eigen::Success || !(prior_ldlt.vectorD().minCoeff() > 0.0)) return out;
  const Matrix6d prior_inv = prior_ldlt.solve(Matrix6d::Identity());

  std::vector<Matrix6d> noise_inv(nd);  // the detection's peak and base, block diagonal; the mid weighs nothing
  for (size_t d = 0; d < nd; ++d) {
    noise_inv[d].setZero();
    for (int i : {0, 2}) noise_inv[d].block<2, 2>(2 * i, 2 * i) = point_cov[d][size_t(i)].inverse();
  }
  // The fit of matched (detection, candidate) pairs: minimise over the pose shift x = (rotation in the
  // camera frame, camera position) J(x) = x' P^-1 x + sum_i r_i(x)' N_i^-1 r_i(x), Gauss-Newton from
  // `start`, every step reprojected (with the prediction's Jacobian at x = 0 one step is the first-order
  // Mahalanobis distance r' (J P J' + N)^-1 r of the stacked points). Returns J and the pose shift.
  struct Fit {
    double cost = INFINITY;
    Vector6d x = Vector6d::Zero();
  };
  const auto fit = [&](const std::vector<std::pair<size_t, size_t>>& pairs, const Vector6d& start) {
    ++out.fits;
    std::vector<ConeCandidate> at(pairs.size());
    const auto project = [&](const Vector6d& x) {
      const Eigen::Matrix3d Rx = Exp(x.head<3>()) * R;
      const Eigen::Vector3d ex = eye + x.tail<3>();
      for (size_t i = 0; i < pairs.size(); ++i)
        if (!ProjectCone(model(size_t(out.candidates[pairs[i].second].cone), ex), Rx, ex, cam, cfg, &at[i], INFINITY))
          return false;
      return true;
    };
    const auto cost_at = [&](const Vector6d& x) {
      if (!project(x)) return double(INFINITY);
      double c = x.dot(prior_inv * x);
      for (size_t i = 0; i < pairs.size(); ++i) {
        const Vector6d r = Stack(dets[pairs[i].first]) - at[i].predicted_px;
        c += r.dot(noise_inv[pairs[i].first] * r);
      }
      return c;
    };
    Fit f;
    f.x = start;
    f.cost = cost_at(f.x);
    if (!std::isfinite(f.cost)) {
      f.x.setZero();
      f.cost = cost_at(f.x);
    }
    for (int it = 0; it < std::max(cfg.fit_iterations, 1) && std::isfinite(f.cost); ++it) {
      if (!project(f.x)) break;
      Matrix6d A = prior_inv;
      Vector6d b = -prior_inv * f.x;
      for (size_t i = 0; i < pairs.size(); ++i) {
        const Matrix6d& Ni = noise_inv[pairs[i].first];
        const Vector6d r = Stack(dets[pairs[i].first]) - at[i].predicted_px;
        A += at[i].jacobian.transpose() * Ni * at[i].jacobian;
        b += at[i].jacobian.transpose() * Ni * r;
      }
      const Vector6d step = A.ldlt().solve(b);
      if (cfg.fit_iterations == 0) {  // first order at the prediction: r' (J P J' + N)^-1 r
        f.cost -= b.dot(step);
        f.x += step;
        break;
      }
      double lambda = 1.0, c = cost_at(f.x + step);
      for (int halving = 0; halving < 6 && !(c < f.cost); ++halving) c = cost_at(f.x + (lambda *= 0.5) * step);
      if (!(c < f.cost)) break;
      const bool converged = f.cost - c < 1e-3 * (1.0 + c);
      f.x += lambda * step, f.cost = c;
      if (converged) break;
    }
    return f;
  };
  // Per pair: its own fit, gated (a cone far from every prediction is no candidate).
  std::vector<std::vector<double>> pair_d2(nd, std::vector<double>(nc, INFINITY));
  std::vector<std::vector<Fit>> pair_fit(nd, std::vector<Fit>(nc));
  for (size_t d = 0; d < nd; ++d)
    for (size_t c = 0; c < nc; ++c) {
      pair_fit[d][c] = fit({{d, c}}, Vector6d::Zero());
      if (pair_fit[d][c].cost < gate) pair_d2[d][c] = pair_fit[d][c].cost;
    }
  std::vector<std::vector<size_t>> order(nd);  // each detection's gated candidates, best first
  for (size_t d = 0; d < nd; ++d) {
    for (size_t c = 0; c < nc; ++c)
      if (std::isfinite(pair_d2[d][c])) order[d].push_back(c);
    std::sort(order[d].begin(), order[d].end(), [&](size_t a, size_t b) { return pair_d2[d][a] < pair_d2[d][b]; });
  }

  // Every injective assignment of gated pairs, scored jointly. Adding a cone to an assignment never
  // lowers its fit's cost, and an unmatched detection costs the gate, so a partial assignment already
  // costlier than the best complete one plus the ambiguity margin can neither win nor be a rival: cut.
  struct Scored {
    std::vector<int> a;  // candidate index per detection, -1 none
    Fit fit;
    int misses = 0;
  };
  // The layout cones an assignment leaves unmatched that its fitted pose puts in plain view, or partly in view where
  // the image has no orange: every layout cone, not only the candidates (the fit may move one into the image),
  // projected unclipped. And the orange boxes its pose puts no cone on, this frame's detections' own aside.
  std::vector<rig_model::ConeSilhouette> detected;
  for (const ConePoints2d& p : dets) detected.push_back(rig_model::DetectedSilhouette(p[0], p[2]));
  const auto negative_at = [&](const Vector6d& x, const std::vector<int>& a, int* misses) {
    *misses = 0;
    if (!(cfg.miss_cost > 0.0) && !(cfg.unexplained_cost > 0.0)) return 0.0;
    const auto silhouettes =
        LayoutSilhouettes(model, num_cones, Exp(x.head<3>()) * R, eye + x.tail<3>(), cam, cfg.min_depth_m);
    std::vector<bool> seen(num_cones, false);
    for (int c : a)
      if (c >= 0) seen[size_t(out.candidates[size_t(c)].cone)] = true;
    if (cfg.miss_cost > 0.0)
      *misses = rig_model::MissedInView(silhouettes, seen, orange, cam.width_px, cam.height_px, cfg.plain_view);
    const int unexplained =
        cfg.unexplained_cost > 0.0
            ? rig_model::UnexplainedOrange(silhouettes, detected, orange, cam.width_px, cam.height_px, cfg.plain_view)
            : 0;
    return cfg.miss_cost * *misses + cfg.unexplained_cost * unexplained;
  };
  std::vector<Scored> all;
  std::vector<int> cur(nd, -1);
  std::vector<bool> used(nc, false);
  std::vector<std::pair<size_t, size_t>> pairs;
  double best_cost = INFINITY;
  std::function<void(size_t, const Fit&, int)> search = [&](size_t d, const Fit& partial, int unmatched) {
    if (out.too_many) return;
    const double lower = partial.cost + gate * double(unmatched);
    if (lower >= best_cost + cfg.ambiguity_margin) return;
    if (size_t(out.fits) >= cfg.max_assignments) {
      out.too_many = true;
      return;
    }
    if (d == nd) {
      int misses = 0;
      const double negative = negative_at(partial.x, cur, &misses);
      all.push_back({cur, partial, misses});
      all.back().fit.cost = lower + negative;
      best_cost = std::min(best_cost, all.back().fit.cost);
      return;
    }
    for (size_t c : order[d]) {
      if (used[c]) continue;
      used[c] = true, cur[d] = int(c);
      pairs.emplace_back(d, c);
      const Fit f = pairs.size() == 1 ? pair_fit[d][c] : fit(pairs, partial.x);
      search(d + 1, f, unmatched);
      pairs.pop_back();
      used[c] = false, cur[d] = -1;
    }
    search(d + 1, partial, unmatched + 1);  // a distractor, or a cone the prediction does not reach
  };
  Fit none;
  none.cost = 0.0;
  search(0, none, 0);
  if (out.too_many || all.empty()) return out;
  const auto best = std::min_element(all.begin(), all.end(),
                                     [](const Scored& x, const Scored& y) { return x.fit.cost < y.fit.cost; });
  out.cost = best->fit.cost;
  out.misses = best->misses;
  const double gate2 = boost::math::quantile(boost::math::chi_squared(2), cfg.gate_probability);
  for (size_t d = 0; d < nd && !out.conflict; ++d) {
    if (best->a[d] >= 0) continue;
    for (size_t c = 0; c < nc; ++c) {
      if (std::count(best->a.begin(), best->a.end(), int(c))) continue;  // explained by another detection
      if (apart_maybe_merged[c]) continue;                               // a blob there may be two cones
      const ConeCandidate& k = out.candidates[c];
      const Eigen::Matrix<double, 2, 6> Jb = k.jacobian.bottomRows<2>();
      const Eigen::Matrix2d S = Jb * prior * Jb.transpose() + point_cov[d][2];
      const Eigen::Vector2d r = dets[d][2] - k.predicted_px.tail<2>();
      if (r.dot(S.ldlt().solve(r)) < gate2) out.conflict = true;
    }
  }
  if (out.conflict) return out;
  for (size_t d = 0; d < nd; ++d) {
    const int c = best->a[d];
    if (c < 0) continue;
    // The nearest rival: any assignment giving this detection another cone.
    double rival = INFINITY;
    for (const Scored& s : all)
      if (s.a[d] >= 0 && s.a[d] != c) rival = std::min(rival, s.fit.cost);
    if (rival - best->fit.cost < cfg.ambiguity_margin) {
      ++out.ambiguous;
      continue;
    }
    out.cone_of_detection[d] = out.candidates[size_t(c)].cone;
    out.d2[d] = pair_d2[d][size_t(c)];
  }
  return out;
}

}  // namespace cone_tracker
