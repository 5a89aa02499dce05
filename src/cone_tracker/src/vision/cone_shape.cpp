#include "cone_tracker/vision/cone_shape.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace cone_tracker {

ConeShapeCheck CheckConeShape(const std::vector<Run>& runs, const Eigen::Vector2d& peak, const Eigen::Vector2d& base,
                              const ConeShapeConfig& c) {
  ConeShapeCheck out;
  const Eigen::Vector2d axis = base - peak;
  const double h = axis.norm();
  if (!c.enabled || !(h >= c.min_height_px) || runs.empty()) return out;
  if (!(base.y() > peak.y())) {
    out.ok = false, out.why = "peak below base";
    return out;
  }
  // Holes: per image row, the pixels between the row's first and last blob pixel that are not blob.
  std::map<int, Eigen::Vector3d> rows;  // y -> (x_min, x_max, pixels)
  for (const Run& r : runs) {
    auto it = rows.find(r.y);
    if (it == rows.end()) it = rows.emplace(r.y, Eigen::Vector3d(r.x0, r.x1, 0.0)).first;
    Eigen::Vector3d& v = it->second;
    v.x() = std::min(v.x(), double(r.x0)), v.y() = std::max(v.y(), double(r.x1)), v.z() += r.x1 - r.x0 + 1;
  }
  double span = 0.0, filled = 0.0;
  for (const auto& [y, v] : rows) span += v.y() - v.x() + 1.0, filled += v.z();
  out.hole_frac = span > 0.0 ? 1.0 - filled / span : 0.0;
  // Width across the axis per bin of height, fitted by a line over the bins that hold pixels (the
  // gaps of white bands hold none).
  const Eigen::Vector2d d = axis / h;
  const int bins = std::clamp(int(h / 2.0), 5, 32);
  std::vector<double> lo(size_t(bins), INFINITY), hi(size_t(bins), -INFINITY);
  for (const Run& r : runs)
    for (int x : {r.x0, r.x1}) {
      const Eigen::Vector2d p = Eigen::Vector2d(x, r.y) - peak;
      const double t = p.dot(d) / h, s = p.x() * d.y() - p.y() * d.x();
      if (t < 0.0 || t >= 1.0) continue;
      const size_t i = size_t(t * bins);
      lo[i] = std::min(lo[i], s), hi[i] = std::max(hi[i], s);
    }
  double n = 0, st = 0, stt = 0, sw = 0, stw = 0;
  std::vector<std::pair<double, double>> tw;
  for (int i = 0; i < bins; ++i) {
    if (!(hi[size_t(i)] >= lo[size_t(i)])) continue;
    const double t = (i + 0.5) / bins, w = hi[size_t(i)] - lo[size_t(i)] + 1.0;
    tw.emplace_back(t, w);
    n += 1, st += t, stt += t * t, sw += w, stw += t * w;
  }
  const double det = n * stt - st * st;
  if (n < 3 || !(det > 0.0)) return out;  // too few rows to judge
  const double slope = (n * stw - st * sw) / det, w0 = (sw - slope * st) / n, w1 = w0 + slope;
  double rss = 0.0;
  for (const auto& [t, w] : tw) rss += (w - w0 - slope * t) * (w - w0 - slope * t);
  out.top_width_frac = w1 > 0.0 ? std::max(0.0, w0) / w1 : INFINITY;
  out.width_rms_frac = w1 > 0.0 ? std::sqrt(rss / n) / w1 : INFINITY;
  if (out.top_width_frac > c.max_top_width_frac)
    out.ok = false, out.why = "width does not taper to the peak";
  else if (out.width_rms_frac > c.max_width_rms_frac)
    out.ok = false, out.why = "outline edges not straight";
  else if (out.hole_frac > c.max_hole_frac)
    out.ok = false, out.why = "holes";
  return out;
}

}  // namespace cone_tracker
