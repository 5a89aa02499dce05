#include "cone_tracker/vision/cone_pose_search.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

#include <Eigen/Eigenvalues>

namespace cone_tracker {
namespace {

Eigen::Vector3d Ray(const CameraModel& cam, const Eigen::Vector2d& uv) {
  return Eigen::Vector3d((uv.x() - cam.cx_px) / cam.fx_px, (uv.y() - cam.cy_px) / cam.fy_px, 1.0).normalized();
}

struct Hypothesis {
  std::vector<int> assignment;
  int matched = 0;
  double cost = 0.0;  // mean squared px of the matched peaks and bases
};

// The world's up direction in the camera frame: normal to every plane through
// the centre of projection and a cone's axis (least squares over the axes,
// dropping the worst while it is off by more than max_off; a distractor's axis
// need not be vertical).
bool UpInCamera(const std::vector<Eigen::Vector3d>& peak, const std::vector<Eigen::Vector3d>& base, double max_off,
                Eigen::Vector3d* up) {
  std::vector<Eigen::Vector3d> normals;
  Eigen::Vector3d along = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < peak.size(); ++i) {
    const Eigen::Vector3d n = peak[i].cross(base[i]);
    if (n.norm() < 1e-9) continue;
    normals.push_back(n.normalized());
    along += peak[i] - base[i];
  }
  while (normals.size() >= 2) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    for (const Eigen::Vector3d& n : normals) A += n * n.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A);
    if (eig.info() != Eigen::Success || !(eig.eigenvalues()(1) > 1e-9)) return false;  // one axis plane only
    *up = eig.eigenvectors().col(0);
    if (up->dot(along) < 0.0) *up = -*up;
    auto worst = normals.begin();
    for (auto it = normals.begin(); it != normals.end(); ++it)
      if (std::abs(it->dot(*up)) > std::abs(worst->dot(*up))) worst = it;
    if (std::abs(worst->dot(*up)) <= max_off || normals.size() <= 3) return true;
    normals.erase(worst);
  }
  return false;
}

// Greedy matching of detections to the layout projected with a rough pose. The pair that made the
// pose (detection i as cone a, j as b) is the hypothesis itself: matched as it is, whatever the rough
// pose's error at its own cones (a near cone seen at the image's edge, its axis off the estimated
// up, can be off its own projection by more than the gate).
Hypothesis MatchAll(const std::vector<ConeDetection>& dets, const std::vector<double>& det_height_px,
                    const std::vector<ConeModel>& cones, const CameraModel& cam, const Eigen::Matrix3d& R,
                    const Eigen::Vector3d& t, const ConeSearchConfig& cfg, size_t i, size_t a, size_t j, size_t b) {
  struct Pair {
    double e;
    int d, c;
  };
  std::vector<Pair> pairs;
  double own_e = 0.0;
  for (size_t c = 0; c < cones.size(); ++c) {
    const Eigen::Vector3d pb = R * cones[c].base_m + t;
    const Eigen::Vector3d pp = R * (cones[c].base_m + Eigen::Vector3d(0, 0, cones[c].height_m)) + t;
    if (!(pb.z() > 0.1 && pp.z() > 0.1)) continue;
    const Eigen::Vector2d base(cam.fx_px * pb.x() / pb.z() + cam.cx_px, cam.fy_px * pb.y() / pb.z() + cam.cy_px);
    const Eigen::Vector2d peak(cam.fx_px * pp.x() / pp.z() + cam.cx_px, cam.fy_px * pp.y() / pp.z() + cam.cy_px);
    for (size_t d = 0; d < dets.size(); ++d) {
      const double gate = std::max(cfg.match_gate_height_frac * det_height_px[d], cfg.match_gate_min_rad * cam.fx_px);
      // In units of the gate: a near cone's pixels are no worse matched than a far one's at the same angle.
      const double e = 0.5 *
                       ((dets[d].peak_undist_px - peak).squaredNorm() + (dets[d].base_undist_px - base).squaredNorm()) /
                       (gate * gate);
      const bool own = (d == i && c == a) || (d == j && c == b);
      if (own)
        pairs.push_back({-1.0, int(d), int(c)}), own_e += e;  // sorted first
      else if (e < 1.0)
        pairs.push_back({e, int(d), int(c)});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.e < b.e; });
  Hypothesis h;
  h.assignment.assign(dets.size(), -1);
  std::vector<bool> used(cones.size(), false);
  for (const Pair& p : pairs) {
    if (h.assignment[size_t(p.d)] >= 0 || used[size_t(p.c)]) continue;
    h.assignment[size_t(p.d)] = p.c, used[size_t(p.c)] = true;
    ++h.matched, h.cost += std::max(p.e, 0.0);
  }
  h.cost += own_e;
  if (h.matched > 0) h.cost /= h.matched;
  return h;
}

}  // namespace

std::vector<std::vector<int>> SearchAssignments(const std::vector<ConeDetection>& dets,
                                                const std::vector<ConeModel>& cones, const CameraModel& cam,
                                                const ConeSearchConfig& cfg) {
  const size_t nd = dets.size(), nc = cones.size();
  std::vector<Eigen::Vector3d> peak(nd), base(nd);
  std::vector<double> height_px(nd);
  for (size_t d = 0; d < nd; ++d) {
    peak[d] = Ray(cam, dets[d].peak_undist_px), base[d] = Ray(cam, dets[d].base_undist_px);
    height_px[d] = (dets[d].peak_undist_px - dets[d].base_undist_px).norm();
  }
  Eigen::Vector3d up;
  if (nd < 3 || !UpInCamera(peak, base, cfg.max_axis_off_rad, &up)) return {};
  // The base of detection d for a cone of unit height: s_b base + up = s_p peak.
  std::vector<Eigen::Vector3d> base_unit(nd);
  std::vector<bool> usable(nd, false);
  for (size_t d = 0; d < nd; ++d) {
    Eigen::Matrix<double, 3, 2> A;
    A << base[d], -peak[d];
    const Eigen::Vector2d s = A.colPivHouseholderQr().solve(-up);
    usable[d] = s(0) > 0.0 && s(1) > 0.0 && height_px[d] > 2.0;
    base_unit[d] = s(0) * base[d];
  }
  // Hypotheses from the largest detections (the nearest, the best measured).
  std::vector<size_t> order(nd);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return height_px[a] > height_px[b]; });
  order.resize(std::min(nd, cfg.max_detections));

  std::vector<Hypothesis> kept;
  std::set<std::vector<int>> seen;
  size_t scored = 0;
  for (size_t ii = 0; ii < order.size() && scored < cfg.max_hypotheses; ++ii)
    for (size_t jj = ii + 1; jj < order.size() && scored < cfg.max_hypotheses; ++jj) {
      const size_t i = order[ii], j = order[jj];
      if (!usable[i] || !usable[j]) continue;
      for (size_t a = 0; a < nc && scored < cfg.max_hypotheses; ++a)
        for (size_t b = 0; b < nc && scored < cfg.max_hypotheses; ++b) {
          if (a == b) continue;
          const Eigen::Vector3d pi = cones[a].height_m * base_unit[i], pj = cones[b].height_m * base_unit[j];
          const Eigen::Vector3d d_cam = pj - pi, d_world = cones[b].base_m - cones[a].base_m;
          const double tol = cfg.spacing_tol_frac * d_world.norm() + cfg.spacing_tol_m;
          const Eigen::Vector3d h_cam = d_cam - d_cam.dot(up) * up;
          const Eigen::Vector2d h_world = d_world.head<2>();
          if (std::abs(d_cam.dot(up) - d_world.z()) > tol || std::abs(h_cam.norm() - h_world.norm()) > tol) continue;
          if (h_world.norm() < 0.2 || h_cam.norm() < 0.1) continue;  // no heading from a vertical pair
          // Rough pose: R maps z to up and the pair's horizontal direction onto its image in the camera.
          Eigen::Matrix3d W, C;
          const Eigen::Vector3d w1(h_world.x() / h_world.norm(), h_world.y() / h_world.norm(), 0.0);
          const Eigen::Vector3d c1 = h_cam.normalized();
          W << w1, Eigen::Vector3d::UnitZ().cross(w1), Eigen::Vector3d::UnitZ();
          C << c1, up.cross(c1), up;
          const Eigen::Matrix3d R = C * W.transpose();
          const Eigen::Vector3d t = 0.5 * (pi + pj) - R * (0.5 * (cones[a].base_m + cones[b].base_m));
          ++scored;
          Hypothesis h = MatchAll(dets, height_px, cones, cam, R, t, cfg, i, a, j, b);
          if (h.matched < 3 || !seen.insert(h.assignment).second) continue;
          kept.push_back(std::move(h));
        }
    }
  std::sort(kept.begin(), kept.end(), [](const Hypothesis& x, const Hypothesis& y) {
    return x.matched != y.matched ? x.matched > y.matched : x.cost < y.cost;
  });
  std::vector<std::vector<int>> out;
  for (size_t k = 0; k < kept.size() && k < std::max(cfg.max_candidates, cfg.max_rivals); ++k)
    out.push_back(kept[k].assignment);
  return out;
}

}  // namespace cone_tracker
