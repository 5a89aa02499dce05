#include "cone_tracker/vision/cone_pose.h"

#include "cone_tracker/vision/cone_pose_search.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numeric>

#include <Eigen/Geometry>

#include <boost/math/distributions/chi_squared.hpp>

#include "pose_math/rotation.h"
#include "rig_model/layout.h"

namespace cone_tracker {

namespace {

using Assignment = std::vector<int>;  // model cone per detection, -1 none

// Up to this many cones and detections every assignment is tried; beyond, the
// pair-hypothesis search (cone_pose_search.h).
constexpr size_t kExhaustiveMax = 8;

Eigen::Vector3d CameraInCones(const pose_math::Pose& T_camera_cones) {
  return -(pose_math::RotationFromQuat(T_camera_cones.q).transpose() * T_camera_cones.t);
}

bool Project(const pose_math::Pose& T_camera_cones, const CameraModel& cam, const Eigen::Vector3d& p_cones,
             Eigen::Vector2d* uv) {
  const Eigen::Vector3d p = pose_math::RotationFromQuat(T_camera_cones.q) * p_cones + T_camera_cones.t;
  if (!(p.z() > 1e-6)) return false;
  *uv = Eigen::Vector2d(cam.fx_px * p.x() / p.z() + cam.cx_px, cam.fy_px * p.y() / p.z() + cam.cy_px);
  return true;
}

// The image of the model's mid point (3.18), from the measured peak and base.
// The detectors give the image midpoint of peak and base, but perspective moves
// the midpoint of a 3-D segment towards its farther end: at 512x384 that was a
// 1.6-2.2 px bias in v on every rig_sim bag (pose_ekf's README, "Status"). The
// image of the midpoint is the harmonic conjugate of the segment's vanishing
// point with respect to its two ends (cross-ratio -1), so it needs only the
// direction of the cone's axis in the camera, i.e. the pose's rotation, which the
// prediction or a first solve gives to well under a degree.
Eigen::Vector2d PerspectiveMidpoint(const Eigen::Vector2d& peak_px, const Eigen::Vector2d& base_px,
                                    const std::array<Eigen::Vector3d, 3>& model, const pose_math::Pose& T_camera_cones,
                                    const CameraModel& cam) {
  const Eigen::Vector3d dir = pose_math::RotationFromQuat(T_camera_cones.q) * (model[2] - model[0]);
  // Vanishing point of dir, homogeneous (w = 0: at infinity, i.e. the plain midpoint).
  const Eigen::Vector3d v(cam.fx_px * dir.x() + cam.cx_px * dir.z(), cam.fy_px * dir.y() + cam.cy_px * dir.z(),
                          dir.z());
  const Eigen::Vector2d seg = base_px - peak_px;
  // Line coordinate s (peak 0, base 1) of the vanishing point: s_v = n / d; the
  // harmonic conjugate of s_v w.r.t. 0 and 1 is s_v / (2 s_v - 1) = n / (2n - d).
  const double n = (v.head<2>() - v.z() * peak_px).dot(seg), d = v.z() * seg.squaredNorm();
  const double s = n / (2.0 * n - d);
  // A vanishing point between peak and base (the camera looking along the axis) has no meaningful midpoint.
  if (!std::isfinite(s) || s <= 0.0 || s >= 1.0) return 0.5 * (peak_px + base_px);
  return peak_px + s * seg;
}

// 3.1.6 with a prediction: enumerate the assignments of detections to model
// cones and keep the cheapest; a pair farther than the gate cannot match.
Assignment AssignByPrediction(const std::vector<ConeDetection>& dets, const std::vector<ConeModel>& cones,
                              const CameraModel& cam, const ConePoseConfig& cfg, const pose_math::Pose& T_pred) {
  const Eigen::Vector3d eye = CameraInCones(T_pred);
  const double gate2 = cfg.max_assignment_px * cfg.max_assignment_px;
  // cost[d][c]: mean squared pixel distance of peak and base, or +inf.
  std::vector<std::vector<double>> cost(dets.size(), std::vector<double>(cones.size(), INFINITY));
  for (size_t c = 0; c < cones.size(); ++c) {
    const auto pts = CorrectedModelPoints(cones[c], eye);
    Eigen::Vector2d peak, base;
    if (!Project(T_pred, cam, pts[0], &peak) || !Project(T_pred, cam, pts[2], &base)) continue;
    for (size_t d = 0; d < dets.size(); ++d) {
      const double e =
          0.5 * ((dets[d].peak_undist_px - peak).squaredNorm() + (dets[d].base_undist_px - base).squaredNorm());
      if (e < gate2) cost[d][c] = e;
    }
  }
  Assignment best(dets.size(), -1), cur(dets.size(), -1);
  double best_cost = INFINITY;
  std::vector<bool> used(cones.size(), false);
  // Unmatched detections cost the gate, so more matches win when they fit.
  std::function<void(size_t, double)> search = [&](size_t d, double sum) {
    if (sum >= best_cost) return;
    if (d == dets.size()) {
      best_cost = sum, best = cur;
      return;
    }
    for (size_t c = 0; c < cones.size(); ++c) {
      if (used[c] || !std::isfinite(cost[d][c])) continue;
      used[c] = true, cur[d] = int(c);
      search(d + 1, sum + cost[d][c]);
      used[c] = false, cur[d] = -1;
    }
    search(d + 1, sum + gate2);
  };
  search(0, 0.0);
  return best;
}

// All injective assignments of up to n detections to the model cones with
// at least three matches (no prediction).
void EnumerateFull(size_t d, size_t n_dets, size_t n_cones, Assignment* cur, std::vector<bool>* used,
                   std::vector<Assignment>* out) {
  if (d == n_dets) {
    if (std::count_if(cur->begin(), cur->end(), [](int c) { return c >= 0; }) >= 3) out->push_back(*cur);
    return;
  }
  for (size_t c = 0; c < n_cones; ++c) {
    if ((*used)[c]) continue;
    (*used)[c] = true, (*cur)[d] = int(c);
    EnumerateFull(d + 1, n_dets, n_cones, cur, used, out);
    (*used)[c] = false, (*cur)[d] = -1;
  }
  if (n_dets > 3) EnumerateFull(d + 1, n_dets, n_cones, cur, used, out);  // a distractor
}

PnpResult SolveOnce(const std::vector<ConeDetection>& dets, const std::vector<ConeModel>& cones, const Assignment& a,
                    const CameraModel& cam, const ConePoseConfig& cfg, const std::optional<pose_math::Pose>& initial,
                    const Eigen::Vector3d& eye, bool covariance) {
  std::vector<Eigen::Vector3d> model;
  std::vector<Eigen::Vector2d> image;
  for (size_t d = 0; d < dets.size(); ++d) {
    if (a[d] < 0) continue;
    const auto pts = CorrectedModelPoints(cones[size_t(a[d])], eye);
    model.insert(model.end(), pts.begin(), pts.end());
    const ConeDetection& det = dets[d];
    image.push_back(det.peak_undist_px);
    image.push_back(initial ? PerspectiveMidpoint(det.peak_undist_px, det.base_undist_px, pts, *initial, cam)
                            : det.mid_undist_px);
    image.push_back(det.base_undist_px);
  }
  CameraModel pinhole = cam;  // detections are undistorted already (3.1.2)
  pinhole.distortion.clear();
  PnpOptions opt;
  opt.sigma_px = cfg.sigma_px;
  opt.compute_covariance = covariance;
  // A rival's fit (no covariance wanted): no restarts from other starts either; a rival that fits
  // converges from the first, and one that does not is no rival.
  if (!covariance) opt.best_restart_rms_factor = INFINITY;
  return SolvePnp(pinhole, model, image, opt, initial);
}

// The surface points (3.1.4) and the image of the mid point depend on where the
// camera is: solve from the prediction's (or, without one, the axis points'),
// then correct both from the solution and solve again until the eye settles.
// rival_only: a rival's fit for the ambiguity test: no covariance, no restarts, one correction of the
// surface points.
PnpResult Solve(const std::vector<ConeDetection>& dets, const std::vector<ConeModel>& cones, const Assignment& a,
                const CameraModel& cam, const ConePoseConfig& cfg, const std::optional<pose_math::Pose>& initial,
                bool rival_only = false) {
  const int kCorrections = rival_only ? 1 : 3;
  constexpr double kSettledM = 1e-3;
  PnpResult r = SolveOnce(dets, cones, a, cam, cfg, initial,
                          initial ? CameraInCones(*initial) : Eigen::Vector3d::Zero().eval(), !rival_only);
  for (int i = 0; i < kCorrections && r.ok; ++i) {
    const Eigen::Vector3d eye = CameraInCones(r.T_camera_model);
    PnpResult again = SolveOnce(dets, cones, a, cam, cfg, r.T_camera_model, eye, !rival_only);
    if (!again.ok) break;
    const double moved_m = (CameraInCones(again.T_camera_model) - eye).norm();
    r = std::move(again);
    if (moved_m < kSettledM) break;
  }
  return r;
}

}  // namespace

PnpResult SolveAssignment(const std::vector<ConeDetection>& dets, const std::vector<ConeModel>& cones,
                          const std::vector<int>& a, const CameraModel& cam, const ConePoseConfig& cfg,
                          const std::optional<pose_math::Pose>& initial) {
  return Solve(dets, cones, a, cam, cfg, initial);
}

double ResidualChi2(const PnpResult& r, double sigma_px) {
  double chi2 = 0.0;
  for (const Eigen::Vector2d& e : r.residuals_px) chi2 += e.squaredNorm() / (sigma_px * sigma_px);
  return chi2;
}

double Chi2Threshold(int dof, double probability) {
  return dof > 0 ? boost::math::quantile(boost::math::chi_squared(dof), probability) : INFINITY;
}

std::vector<ConeModel> ConeModels(const rig_model::Layout& layout) {
  std::vector<ConeModel> cones;
  for (const rig_model::ConeSpec& spec : layout.cones)
    cones.push_back({spec.base_m, spec.height_m, spec.tau, spec.collars});
  return cones;
}

std::vector<std::pair<double, double>> CommonCollars(const std::vector<ConeModel>& cones) {
  for (const ConeModel& c : cones)
    if (c.collars != cones.front().collars) return {};
  return cones.empty() ? std::vector<std::pair<double, double>>() : cones.front().collars;
}

std::array<Eigen::Vector3d, 3> CorrectedModelPoints(const ConeModel& cone, const Eigen::Vector3d& eye) {
  return rig_model::CorrectedModelPoints(cone.base_m, cone.height_m, cone.tau, eye);  // (3.18), shared with pose_ekf
}

ModelPointsAt LayoutSeenFrom(const std::vector<ConeModel>& cones) {
  return [&cones](size_t c, const Eigen::Vector3d& eye) { return CorrectedModelPoints(cones[c], eye); };
}

bool LayoutHasRotationalSymmetry(const std::vector<ConeModel>& cones) {
  const size_t n = cones.size();
  if (n < 2 || n > 8) return false;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const ConeModel& c : cones) centroid += c.base_m.head<2>() / double(n);
  std::vector<int> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  while (std::next_permutation(perm.begin(), perm.end())) {
    double cross = 0.0, dot = 0.0;
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector2d a = cones[i].base_m.head<2>() - centroid,
                            b = cones[size_t(perm[i])].base_m.head<2>() - centroid;
      cross += a.x() * b.y() - a.y() * b.x(), dot += a.dot(b);
    }
    const double th = std::atan2(cross, dot);
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(th).toRotationMatrix();
    bool same = true;
    for (size_t i = 0; i < n && same; ++i) {
      const ConeModel &a = cones[i], &b = cones[size_t(perm[i])];
      same = (R * (a.base_m.head<2>() - centroid) - (b.base_m.head<2>() - centroid)).norm() < 1e-3 &&
             std::abs(a.base_m.z() - b.base_m.z()) < 1e-3 && std::abs(a.height_m - b.height_m) < 1e-3;
    }
    if (same) return true;
  }
  return false;
}

std::string ConePoseConfig::Validate() const {
  if (!(sigma_px > 0.0)) return "sigma_px must be > 0";
  if (!(max_assignment_px > 0.0)) return "max_assignment_px must be > 0";
  if (!(chi2_probability > 0.0 && chi2_probability < 1.0)) return "chi2_probability must be in (0, 1)";
  if (!(max_translation_change_m > 0.0)) return "max_translation_change_m must be > 0";
  if (!(max_rotation_change_deg > 0.0)) return "max_rotation_change_deg must be > 0";
  if (!(ambiguity_margin >= 0.0)) return "ambiguity_margin must be >= 0";
  return "";
}

ConePoseResult EstimateConePose(const std::vector<ConeDetection>& dets, const std::vector<ConeModel>& cones,
                                const CameraModel& cam, const ConePoseConfig& cfg,
                                const std::optional<pose_math::Pose>& T_pred) {
  ConePoseResult out;
  out.cone_of_detection.assign(dets.size(), -1);
  if (dets.size() < 3 || cones.size() < 3) {
    out.rejected_by = kPoseTooFewCones;
    out.error = "fewer than 3 cones detected";
    return out;
  }
  if (T_pred) {
    const Assignment a = AssignByPrediction(dets, cones, cam, cfg, *T_pred);
    if (std::count_if(a.begin(), a.end(), [](int c) { return c >= 0; }) < 3) {
      out.rejected_by = kPoseTooFewCones;
      out.error = "fewer than 3 cones match the prediction";
      return out;
    }
    out.cone_of_detection = a;
    out.pnp = Solve(dets, cones, a, cam, cfg, T_pred);
  } else {
    std::vector<Assignment> all;
    std::vector<std::optional<pose_math::Pose>> starts;  // the search's rough pose per assignment
    const ConeSearchConfig search;
    if (dets.size() <= kExhaustiveMax && cones.size() <= kExhaustiveMax) {
      Assignment cur(dets.size(), -1);
      std::vector<bool> used(cones.size(), false);
      EnumerateFull(0, dets.size(), cones.size(), &cur, &used, &all);
      starts.resize(all.size());
    } else {
      for (SearchCandidate& c : SearchAssignments(dets, cones, cam, search)) {  // large layouts: bounded work
        all.push_back(std::move(c.assignment));
        starts.emplace_back(c.rough_T_camera_cones);
      }
      if (all.empty()) {
        out.rejected_by = kPoseTooFewCones;
        out.error = "no 3 detections fit the layout's spacing";
        return out;
      }
    }
    // Most matches first, then the lowest residual; near-ties (symmetric
    // layouts) go to the heading prior when there is one.
    double best_score = INFINITY;
    const bool searched = !(dets.size() <= kExhaustiveMax && cones.size() <= kExhaustiveMax);
    struct Solved {
      Assignment a;
      int matched;
      double chi2;
      bool consistent;
    };
    std::vector<Solved> solved;
    int best_matched = 0;
    for (size_t k = 0; k < all.size(); ++k) {
      Assignment a = all[k];
      // Once a candidate fitted every detection well, the rest are only checked as its rivals; so
      // are those beyond the search's max_candidates.
      const bool rival_only = best_matched > 0 || (searched && k >= search.max_candidates);
      // From the search's rough pose (skips the linear start; a rival then costs two short refinements),
      // from the linear start should that fail (the rough pose may put a cone behind the camera).
      PnpResult r = Solve(dets, cones, a, cam, cfg, starts[k], rival_only);
      if (!r.ok && starts[k]) r = Solve(dets, cones, a, cam, cfg, std::nullopt, rival_only);
      if (!r.ok) continue;
      if (searched && !rival_only) {  // the rough pose's gate may have missed a cone: match again at the solved pose
        const Assignment again = AssignByPrediction(dets, cones, cam, cfg, r.T_camera_model);
        const auto n = [](const Assignment& x) {
          return std::count_if(x.begin(), x.end(), [](int c) { return c >= 0; });
        };
        if (n(again) > n(a)) {
          const PnpResult r2 = Solve(dets, cones, again, cam, cfg, std::nullopt);
          if (r2.ok) r = r2, a = again;
        }
      }
      const int matched = int(std::count_if(a.begin(), a.end(), [](int c) { return c >= 0; }));
      // Searched candidates come most matches first: once one with every detection fitted well is
      // found, only candidates matching as many can still be its rivals.
      if (searched && matched < best_matched) break;
      double score = r.reproj_rms_px - 100.0 * matched;
      // A wrong hypothesis may gather more (distractor) matches than the right one, but not fit them.
      const bool consistent = r.reproj_rms_px <= std::max(search.max_consistent_rms_px, 3.0 * cfg.sigma_px);
      if (searched && !consistent) score += 1e4;
      if (searched) solved.push_back({a, matched, ResidualChi2(r, cfg.sigma_px), consistent});
      if (rival_only) continue;
      if (std::isfinite(cfg.initial_heading_rad)) {
        const Eigen::Vector3d eye = CameraInCones(r.T_camera_model);
        const double dh = std::remainder(std::atan2(eye.y(), eye.x()) - cfg.initial_heading_rad, 2.0 * M_PI);
        score += 0.5 * std::abs(dh);  // breaks ties of equal residual only
      }
      if (score < best_score) best_score = score, out.pnp = r, out.cone_of_detection = a;
      if (searched && matched == int(dets.size()) && r.reproj_rms_px <= 1.5 * cfg.sigma_px)
        best_matched = std::max(best_matched, matched);
    }
    // A rival: a consistent solution as good in matches that gives some detection another cone; if
    // it passes the 6.4.1 gate too, within ambiguity_margin of the best (below), two self-consistent
    // poses and nothing in this frame to choose.
    const int n_best =
        int(std::count_if(out.cone_of_detection.begin(), out.cone_of_detection.end(), [](int c) { return c >= 0; }));
    for (const Solved& s : solved) {
      if (!s.consistent || s.matched < n_best || s.a == out.cone_of_detection) continue;
      bool differs = false;
      for (size_t d = 0; d < s.a.size(); ++d)
        differs |= s.a[d] >= 0 && out.cone_of_detection[d] >= 0 && s.a[d] != out.cone_of_detection[d];
      if (differs && s.chi2 < out.rival_chi2) out.rival_chi2 = s.chi2, out.rival_cone_of_detection = s.a;
    }
  }
  if (!out.pnp.ok) {
    out.rejected_by |= kPoseSolverFailed;
    out.error = "pose solver failed: " + out.pnp.error;
    return out;
  }
  // 6.4.1: χ² of the image residuals (6.2), gated by its CDF (6.3), with 2N - 6 dof
  // (the thesis's k = 2n less the six fitted pose parameters).
  const int dof = out.chi2_dof = int(out.pnp.residuals_px.size()) * 2 - 6;
  out.chi2 = ResidualChi2(out.pnp, cfg.sigma_px);
  out.chi2_threshold = Chi2Threshold(dof, cfg.chi2_probability);
  if (out.chi2 > out.chi2_threshold) out.rejected_by |= kPoseChi2;
  if (out.rival_chi2 <= out.chi2_threshold && out.rival_chi2 < out.chi2 + cfg.ambiguity_margin) {
    out.rejected_by |= kPoseAmbiguous;
    out.error = "another assignment of the cones fits too (chi2 " + std::to_string(out.rival_chi2) + ")";
  }
  // 6.4.2: the change against the prediction.
  if (T_pred) {
    out.motion_checked = true;
    out.translation_change_m = (CameraInCones(out.pnp.T_camera_model) - CameraInCones(*T_pred)).norm();
    out.rotation_change_deg = pose_math::RotationErrorRad(out.pnp.T_camera_model, *T_pred) * 180.0 / M_PI;
    if (!cfg.WithinMotionGate(out.translation_change_m, out.rotation_change_deg)) out.rejected_by |= kPoseMotion;
  }
  out.ok = out.rejected_by == 0;
  if (!out.ok && out.error.empty()) out.error = "rejected by a gate";
  return out;
}

}  // namespace cone_tracker
