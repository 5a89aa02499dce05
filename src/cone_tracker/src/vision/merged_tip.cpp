#include "cone_tracker/vision/merged_tip.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "cone_tracker/vision/segmenter.h"

namespace cone_tracker {
namespace {

// Signed distance of an undistorted point to a line (positive inside the silhouette).
double Distance(const Eigen::Vector3d& line, const Eigen::Vector2d& p) {
  return (line.head<2>().dot(p) + line.z()) / line.head<2>().norm();
}

// Where `line`, through the apex, is top_t along the axis: apex + t d + s e with line . (apex + t d + s e) = 0.
Eigen::Vector2d Corner(const Eigen::Vector3d& line, const Eigen::Vector2d& apex, const Eigen::Vector2d& d, double t) {
  const Eigen::Vector2d e(d.y(), -d.x());
  const double across = line.head<2>().dot(e);
  if (std::abs(across) < 1e-9) return apex + t * d;
  return apex + t * d - (t * line.head<2>().dot(d) / across) * e;
}

}  // namespace

bool MakeTipWedge(const OutlineFit& fit, const Eigen::Vector2d& d, double top_t, const CameraModel& camera,
                  TipWedge* w) {
  const Eigen::Vector2d& apex = fit.apex_undist_px;
  std::vector<Eigen::Vector2d> corners = {apex, Corner(fit.left_line, apex, d, top_t),
                                          Corner(fit.right_line, apex, d, top_t)};
  if (!(top_t > 0.0) || !DistortPixels(camera, &corners)) return false;
  double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
  for (const Eigen::Vector2d& c : corners)
    x_lo = std::min(x_lo, c.x()), x_hi = std::max(x_hi, c.x()), y_lo = std::min(y_lo, c.y()),
    y_hi = std::max(y_hi, c.y());
  w->apex_undist_px = apex, w->axis_dir = d, w->left_line = fit.left_line, w->right_line = fit.right_line;
  w->top_t_px = top_t;
  w->x0 = int(std::floor(x_lo)) - 2, w->x1 = int(std::ceil(x_hi)) + 2;
  w->y0 = int(std::floor(y_lo)) - 2, w->y1 = int(std::ceil(y_hi)) + 2;
  return true;
}

TipPiece FindTipIn(const std::vector<Run>& other, const TipWedge& w, const CameraModel& camera, double edge_px,
                   int width_px) {
  TipPiece out;
  const Eigen::Vector2d &apex = w.apex_undist_px, &d = w.axis_dir;
  const int bx0 = w.x0, bx1 = w.x1, by0 = w.y0, by1 = w.y1;
  const double top_t = w.top_t_px;
  // Per run crossing the box: its pixel centres there, and its two outer boundaries, undistorted in one call.
  std::vector<size_t> crossing;
  std::vector<Eigen::Vector2d> pts;
  for (size_t i = 0; i < other.size(); ++i) {
    const Run& r = other[i];
    if (r.y < by0 || r.y > by1 || r.x1 < bx0 || r.x0 > bx1) {
      out.rest.push_back(r);
      continue;
    }
    crossing.push_back(i);
    pts.emplace_back(r.x0 - 0.5, r.y), pts.emplace_back(r.x1 + 0.5, r.y);
    for (int x = std::max(r.x0, bx0); x <= std::min(r.x1, bx1); ++x) pts.emplace_back(x, r.y);
  }
  if (crossing.empty() || !UndistortPixels(camera, &pts)) {
    out.rest = other;
    out.tip.clear();
    return out;
  }
  std::map<int, std::pair<bool, bool>> row_edges;  // per tip row: ends on the left line, on the right line
  double base_t = -INFINITY;
  size_t k = 0;
  for (size_t i : crossing) {
    const Run& r = other[i];
    const Eigen::Vector2d left_end = pts[k], right_end = pts[k + 1];
    k += 2;
    const int x0 = std::max(r.x0, bx0), x1 = std::min(r.x1, bx1);
    // The inside pixels of this run (one interval: the wedge is convex), and around them those within half a pixel
    // outside an edge: the tip's mixed edge pixels, which go to neither blob (in the tip they would push its edge
    // outward, and in the far cone they would stick out of its outline).
    int tip0 = -1, tip1 = -1, claim0 = -1, claim1 = -1;
    for (int x = x0; x <= x1; ++x, ++k) {
      const Eigen::Vector2d& p = pts[k];
      const double t = (p - apex).dot(d), in = std::min(Distance(w.left_line, p), Distance(w.right_line, p));
      if (in < -0.5 || t < -0.5 || t > top_t) continue;
      if (claim0 < 0) claim0 = x;
      claim1 = x;
      if (in < 0.0 || t < 0.0) continue;
      if (tip0 < 0) tip0 = x;
      tip1 = x;
      if (t > base_t) base_t = t, out.base_end_px = Eigen::Vector2d(x, r.y);
    }
    if (claim0 > r.x0) out.rest.push_back({r.y, r.x0, claim0 - 1});
    if (claim0 < 0)
      out.rest.push_back(r);
    else if (claim1 < r.x1)
      out.rest.push_back({r.y, claim1 + 1, r.x1});
    if (tip0 < 0) continue;
    out.tip.push_back({r.y, tip0, tip1});
    auto& e = row_edges[r.y];
    e.first = e.first || (claim0 == r.x0 && r.x0 > 0 && std::abs(Distance(w.left_line, left_end)) <= edge_px);
    e.second =
        e.second || (claim1 == r.x1 && r.x1 < width_px - 1 && std::abs(Distance(w.right_line, right_end)) <= edge_px);
  }
  int left = 0, right = 0;
  for (const auto& [y, e] : row_edges) left += e.first, right += e.second;
  out.rows = int(row_edges.size());
  out.edge_rows = std::max(left, right);
  return out;
}

}  // namespace cone_tracker

namespace cone_tracker {

// Segmenter's step after the gates (segmenter.h). A blob whose outline's edges fit but whose tip stops short of their
// apex by more than the tip zone takes another blob's pixels that lie between its edges, up to the apex, when
//  - they show one of its edges against the background on at least half of their rows, 3 rows at least (a tip
//    whose two edges are both over the far cone is not seen), and nothing orange lies just past the apex (a tip
//    whose apex is over the far cone does not show where it ends: the edges, extrapolated, say, and the far cone's
//    pixels fill the wedge up to wherever they put it);
//  - what lies between its top and them is a band (Segmenter::IsBand, the test MergeAlongAxes joins across);
//  - the blob with them has one cone's outline (FitConeOutline: the tip check too).
// Both are judged again: the near cone may still fail another gate (its base cut by the image's edge, say), and the
// other blob, with the rest, is judged without the cone in front of it: that cone's body below its base is not the
// body of a collared tip (Measure's "orange below the base").
void Segmenter::SplitMergedTips(std::vector<ConeDetection>* dets, const std::vector<OutlineFit>& fits,
                                const MaskView& mask, const CameraModel& camera) const {
  if (config_.refinement() != PeakRefinement::kOutline || !config_.split_merged_tips) return;
  std::vector<bool> emptied(dets->size(), false);
  for (size_t i = 0; i < dets->size(); ++i) {
    const ConeDetection& near = (*dets)[i];
    const OutlineFit& fit = fits[i];
    if (emptied[i] || near.accepted() || fit.ok || !(fit.tip_short_px > fit.tip_zone_px)) continue;
    std::vector<Eigen::Vector2d> ends = {near.peak_px, near.base_px};  // the line search's, raw
    if (!UndistortPixels(camera, &ends)) continue;
    const Eigen::Vector2d d = (ends[1] - fit.apex_undist_px).normalized();
    const double top_t = (ends[0] - fit.apex_undist_px).dot(d);
    const Eigen::Vector2d down = (near.base_px - near.peak_px).normalized();
    TipWedge wedge;
    std::vector<Eigen::Vector2d> apex = {fit.apex_undist_px};
    if (!MakeTipWedge(fit, d, top_t, camera, &wedge) || !DistortPixels(camera, &apex)) continue;
    // Orange 1.5-4 px past the apex, on the axis or a pixel beside it: where the tip ends is not seen.
    if (MaskHitAlong(mask, apex[0], -down, 1.5, 4.0, 0.5, 1.0)) continue;
    for (size_t j = 0; j < dets->size(); ++j) {
      if (j == i || emptied[j]) continue;
      TipPiece piece = FindTipIn((*dets)[j].blob.runs, wedge, camera, config_.outline.outlier_px, mask.width);
      if (piece.rows < 3 || 2 * piece.edge_rows < piece.rows) continue;
      const double half_width = 0.3 * WidthAcross(piece.tip, piece.base_end_px, down);
      if ((piece.base_end_px - near.peak_px).norm() >= 1.0 && !IsBand(near.peak_px, piece.base_end_px, half_width))
        continue;
      std::vector<Run> joined = near.blob.runs;
      joined.insert(joined.end(), piece.tip.begin(), piece.tip.end());
      OutlineFit whole_fit;
      ConeDetection whole = Judge(BlobOfRuns(std::move(joined)), mask, camera, &whole_fit);
      if (!whole_fit.ok || (whole.failed_gates & kGateOutline)) continue;
      emptied[j] = piece.rest.empty();
      if (!emptied[j]) {
        std::vector<uint8_t> behind(mask.data, mask.data + size_t(mask.height) * size_t(mask.step));
        for (const Run& r : whole.blob.runs)
          std::fill_n(behind.begin() + long(r.y) * mask.step + r.x0, r.x1 - r.x0 + 1, 0);
        (*dets)[j] = Judge(BlobOfRuns(std::move(piece.rest)),
                           MaskView{behind.data(), mask.width, mask.height, mask.step}, camera);
      }
      (*dets)[i] = std::move(whole);
      break;
    }
  }
  for (size_t i = dets->size(); i-- > 0;)
    if (emptied[i]) dets->erase(dets->begin() + long(i));
}

}  // namespace cone_tracker
