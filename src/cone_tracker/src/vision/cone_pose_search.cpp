#include "cone_tracker/vision/cone_pose_search.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <set>

#include <Eigen/Eigenvalues>

#include "pose_math/rotation.h"

namespace cone_tracker {
namespace {

Eigen::Vector3d Ray(const CameraModel& cam, const Eigen::Vector2d& uv) {
  return Eigen::Vector3d((uv.x() - cam.cx_px) / cam.fx_px, (uv.y() - cam.cy_px) / cam.fy_px, 1.0).normalized();
}

struct Hypothesis {
  std::vector<int> assignment;
  pose_math::Pose rough;  // T_camera_cones
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

struct MatchPair {
  double e;  // in units of the gate squared; -1 for the hypothesis's own pair
  int d, c;
};

// For each (detection i, cone a), the bitset over (detection k, cone c) of spacing_fits(i, a, k, c),
// filled when first asked for: O(D N) per (i, a), at most O(D^2 N^2) per frame, like the pair checks.
// A pair hypothesis (i as a, j as b) can only be joined by a detection k as a cone c whose spacing
// fits both of its cones: the AND of two rows lists them, so the rough match projects only those
// cones instead of the whole layout (hundreds of pair hypotheses per frame with 30 cones).
template <typename Fits>
class SpacingTable {
 public:
  SpacingTable(size_t n_dets, size_t n_cones, Fits fits)
      : nd_(n_dets), nc_(n_cones), words_((n_dets * n_cones + 63) / 64), fits_(fits), rows_(n_dets * n_cones) {}

  // The (k, c) that fit both i as a and j as b, k not i or j and c not a or b, into *out (cleared).
  void Joiners(size_t i, size_t a, size_t j, size_t b, std::vector<MatchPair>* out) {
    out->clear();
    const std::vector<uint64_t>&x = Row(i, a), &y = Row(j, b);
    for (size_t w = 0; w < words_; ++w)
      for (uint64_t m = x[w] & y[w]; m != 0; m &= m - 1) {
        const size_t bit = w * 64 + size_t(__builtin_ctzll(m)), k = bit / nc_, c = bit % nc_;
        if (k != i && k != j && c != a && c != b) out->push_back({0.0, int(k), int(c)});
      }
  }

 private:
  const std::vector<uint64_t>& Row(size_t i, size_t a) {
    std::vector<uint64_t>& row = rows_[i * nc_ + a];
    if (!row.empty()) return row;
    row.assign(words_, 0);
    for (size_t k = 0; k < nd_; ++k)
      for (size_t c = 0; c < nc_; ++c)
        if (k != i && c != a && fits_(i, a, k, c)) row[(k * nc_ + c) / 64] |= uint64_t(1) << ((k * nc_ + c) % 64);
    return row;
  }

  size_t nd_, nc_, words_;
  Fits fits_;
  std::vector<std::vector<uint64_t>> rows_;
};

// Greedy matching of detections to the layout projected with a rough pose, over the candidate pairs
// (detection, cone) in *pairs (their e is filled in here). The pair that made the pose (detection i
// as cone a, j as b) is the hypothesis itself: matched as it is, whatever the rough pose's error at
// its own cones (a near cone seen at the image's edge, its axis off the estimated up, can be off its
// own projection by more than the gate).
Hypothesis MatchAll(const std::vector<ConeDetection>& dets, const std::vector<double>& det_height_px,
                    const std::vector<ConeModel>& cones, const CameraModel& cam, const Eigen::Matrix3d& R,
                    const Eigen::Vector3d& t, const ConeSearchConfig& cfg, size_t i, size_t a, size_t j, size_t b,
                    std::vector<MatchPair>* pairs) {
  // In units of the gate: a near cone's pixels are no worse matched than a far one's at the same angle.
  const auto error = [&](size_t d, size_t c) {
    const Eigen::Vector3d pb = R * cones[c].base_m + t;
    const Eigen::Vector3d pp = R * (cones[c].base_m + Eigen::Vector3d(0, 0, cones[c].height_m)) + t;
    if (!(pb.z() > 0.1 && pp.z() > 0.1)) return double(INFINITY);
    const Eigen::Vector2d base(cam.fx_px * pb.x() / pb.z() + cam.cx_px, cam.fy_px * pb.y() / pb.z() + cam.cy_px);
    const Eigen::Vector2d peak(cam.fx_px * pp.x() / pp.z() + cam.cx_px, cam.fy_px * pp.y() / pp.z() + cam.cy_px);
    const double gate = std::max(cfg.match_gate_height_frac * det_height_px[d], cfg.match_gate_min_rad * cam.fx_px);
    return 0.5 * ((dets[d].peak_undist_px - peak).squaredNorm() + (dets[d].base_undist_px - base).squaredNorm()) /
           (gate * gate);
  };
  pairs->erase(std::remove_if(pairs->begin(), pairs->end(),
                              [&](MatchPair& p) { return !((p.e = error(size_t(p.d), size_t(p.c))) < 1.0); }),
               pairs->end());
  Hypothesis h;
  if (pairs->empty()) {  // most hypotheses: no third match, no assignment to build
    h.matched = 2;
    return h;
  }
  const double own_e = error(i, a) + error(j, b);
  pairs->push_back({-1.0, int(i), int(a)}), pairs->push_back({-1.0, int(j), int(b)});  // sorted first
  std::sort(pairs->begin(), pairs->end(), [](const MatchPair& x, const MatchPair& y) { return x.e < y.e; });
  h.assignment.assign(dets.size(), -1);
  std::vector<bool> used(cones.size(), false);
  for (const MatchPair& p : *pairs) {
    if (h.assignment[size_t(p.d)] >= 0 || used[size_t(p.c)]) continue;
    h.assignment[size_t(p.d)] = p.c, used[size_t(p.c)] = true;
    ++h.matched, h.cost += std::max(p.e, 0.0);
  }
  h.cost += own_e;
  h.cost /= h.matched;
  return h;
}

}  // namespace

std::vector<SearchCandidate> SearchAssignments(const std::vector<ConeDetection>& dets,
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

  // Detection i as cone a and k as c: their bases (from the detections' axes and the cones' heights)
  // as far apart, vertically and horizontally, as the layout's, within the spacing tolerance. Asked
  // thousands of times per frame: the bases in the camera and the layout's spacings are tabled first.
  std::vector<Eigen::Vector3d> base_cam(nd * nc);  // detection d as cone c
  for (size_t d = 0; d < nd; ++d)
    for (size_t c = 0; c < nc; ++c) base_cam[d * nc + c] = cones[c].height_m * base_unit[d];
  struct Spacing {
    double tol, dz, horizontal;
  };
  std::vector<Spacing> spacing(nc * nc);  // from cone a to cone c
  for (size_t a = 0; a < nc; ++a)
    for (size_t c = 0; c < nc; ++c) {
      const Eigen::Vector3d d_world = cones[c].base_m - cones[a].base_m;
      spacing[a * nc + c] = {cfg.spacing_tol_frac * d_world.norm() + cfg.spacing_tol_m, d_world.z(),
                             d_world.head<2>().norm()};
    }
  const auto spacing_fits = [&](size_t i, size_t a, size_t k, size_t c) {
    const Spacing& w = spacing[a * nc + c];
    const Eigen::Vector3d d_cam = base_cam[k * nc + c] - base_cam[i * nc + a];
    const double v_cam = d_cam.dot(up);
    return std::abs(v_cam - w.dz) <= w.tol && std::abs((d_cam - v_cam * up).norm() - w.horizontal) <= w.tol;
  };
  // Joiners need every detection's base; without one (an axis along a viewing ray) every hypothesis
  // is matched against the whole layout, as without the table.
  const bool all_usable = std::all_of(usable.begin(), usable.end(), [](bool u) { return u; });
  SpacingTable<decltype(spacing_fits)> table(nd, nc, spacing_fits);
  std::vector<MatchPair> joiners;
  std::vector<Hypothesis> kept;
  std::set<std::vector<int>> seen;
  size_t scored = 0;
  for (size_t ii = 0; ii < order.size() && scored < cfg.max_hypotheses; ++ii)
    for (size_t jj = ii + 1; jj < order.size() && scored < cfg.max_hypotheses; ++jj) {
      const size_t i = order[ii], j = order[jj];
      if (!usable[i] || !usable[j]) continue;
      for (size_t a = 0; a < nc && scored < cfg.max_hypotheses; ++a)
        for (size_t b = 0; b < nc && scored < cfg.max_hypotheses; ++b) {
          if (a == b || !spacing_fits(i, a, j, b)) continue;
          const Eigen::Vector3d &pi = base_cam[i * nc + a], &pj = base_cam[j * nc + b];
          const Eigen::Vector3d d_cam = pj - pi, h_cam = d_cam - d_cam.dot(up) * up;
          const Eigen::Vector2d h_world = (cones[b].base_m - cones[a].base_m).head<2>();
          const double h_world_m = spacing[a * nc + b].horizontal;
          if (h_world_m < 0.2 || h_cam.norm() < 0.1) continue;  // no heading from a vertical pair
          if (all_usable) {
            table.Joiners(i, a, j, b, &joiners);
            if (joiners.empty()) continue;
          } else {
            joiners.clear();
            for (size_t k = 0; k < nd; ++k)
              for (size_t c = 0; c < nc; ++c)
                if (k != i && k != j && c != a && c != b) joiners.push_back({0.0, int(k), int(c)});
          }
          // Rough pose: R maps z to up and the pair's horizontal direction onto its image in the camera.
          Eigen::Matrix3d W, C;
          const Eigen::Vector3d w1(h_world.x() / h_world_m, h_world.y() / h_world_m, 0.0);
          const Eigen::Vector3d c1 = h_cam.normalized();
          W << w1, Eigen::Vector3d::UnitZ().cross(w1), Eigen::Vector3d::UnitZ();
          C << c1, up.cross(c1), up;
          const Eigen::Matrix3d R = C * W.transpose();
          const Eigen::Vector3d t = 0.5 * (pi + pj) - R * (0.5 * (cones[a].base_m + cones[b].base_m));
          ++scored;
          Hypothesis h = MatchAll(dets, height_px, cones, cam, R, t, cfg, i, a, j, b, &joiners);
          if (h.matched < 3 || !seen.insert(h.assignment).second) continue;
          h.rough = {pose_math::QuatFromRotation(R), t};
          kept.push_back(std::move(h));
        }
    }
  std::sort(kept.begin(), kept.end(), [](const Hypothesis& x, const Hypothesis& y) {
    return x.matched != y.matched ? x.matched > y.matched : x.cost < y.cost;
  });
  std::vector<SearchCandidate> out;
  for (size_t k = 0; k < kept.size() && k < std::max(cfg.max_candidates, cfg.max_rivals); ++k)
    out.push_back({std::move(kept[k].assignment), kept[k].rough});
  return out;
}

}  // namespace cone_tracker
