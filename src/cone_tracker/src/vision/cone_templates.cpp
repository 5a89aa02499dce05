#include "cone_tracker/vision/cone_templates.h"

#include <algorithm>
#include <cmath>

namespace cone_tracker {

namespace {

constexpr double kDeg = M_PI / 180.0;

// Parabola vertex offset through three samples at -1, 0, +1 (0 when flat).
double Vertex(double m, double c, double p) {
  const double den = m - 2.0 * c + p;
  return den < 0.0 ? std::clamp(0.5 * (m - p) / den, -0.5, 0.5) : 0.0;
}

}  // namespace

ConeTemplateSet::ConeTemplateSet(const TemplateSetConfig& c) : config_(c) {
  n_height_ = std::max(1, int(std::floor((c.max_height_px - c.min_height_px) / c.height_step_px)) + 1);
  n_orient_ = 2 * int(std::floor(c.max_tilt_deg / c.orientation_step_deg)) + 1;
  templates_.resize(size_t(n_height_) * n_orient_);
  for (int hi = 0; hi < n_height_; ++hi)
    for (int oi = 0; oi < n_orient_; ++oi) {
      const double h = c.min_height_px + hi * c.height_step_px;
      const double theta = (90.0 + (oi - n_orient_ / 2) * c.orientation_step_deg) * kDeg;
      const Eigen::Vector2d d(std::cos(theta), std::sin(theta)), e(-d.y(), d.x());
      const Eigen::Vector2d v[3] = {Eigen::Vector2d::Zero(), h * d + c.tau * h * e, h * d - c.tau * h * e};
      Template& t = templates_[size_t(hi) * n_orient_ + size_t(oi)];
      const int y_lo = int(std::ceil(std::min({v[0].y(), v[1].y(), v[2].y()})));
      const int y_hi = int(std::floor(std::max({v[0].y(), v[1].y(), v[2].y()})));
      t.row0 = y_lo;
      t.min_x = INT32_MAX, t.max_x = INT32_MIN;
      for (int y = y_lo; y <= y_hi; ++y) {
        double xl = INFINITY, xr = -INFINITY;
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector2d& p = v[k];
          const Eigen::Vector2d& q = v[(k + 1) % 3];
          if ((y < std::min(p.y(), q.y())) || (y > std::max(p.y(), q.y())) || p.y() == q.y()) continue;
          const double x = p.x() + (y - p.y()) * (q.x() - p.x()) / (q.y() - p.y());
          xl = std::min(xl, x), xr = std::max(xr, x);
        }
        const int x0 = int(std::ceil(xl - 1e-9)), x1 = int(std::floor(xr + 1e-9));  // centres on an edge are inside
        t.x0.push_back(int16_t(x0)), t.x1.push_back(int16_t(x1));
        if (x1 >= x0) t.count += x1 - x0 + 1, t.min_x = std::min(t.min_x, x0), t.max_x = std::max(t.max_x, x1);
      }
      // The template image: the triangle on a black margin, without which a
      // shorter triangle correlates perfectly with the top of a taller one.
      const int margin = 2 + int(0.05 * h);
      t.win_x0 = t.min_x - margin, t.win_x1 = t.max_x + margin;
      t.win_y0 = t.row0 - margin, t.win_y1 = t.row0 + int(t.x0.size()) - 1 + margin;
    }
}

TemplateMatch ConeTemplateSet::Refine(const MaskView& mask, const Eigen::Vector2d& peak_guess,
                                      const Eigen::Vector2d& base_guess, int search_px) const {
  TemplateMatch best;
  const Eigen::Vector2d axis = base_guess - peak_guess;
  const double tilt_deg = std::atan2(axis.y(), axis.x()) / kDeg - 90.0;
  const int hc = std::clamp(int(std::lround((axis.norm() - config_.min_height_px) / config_.height_step_px)), 0,
                            n_height_ - 1);
  const int oc = std::clamp(int(std::lround(tilt_deg / config_.orientation_step_deg)) + n_orient_ / 2, 0, n_orient_ - 1);
  const int ax = int(std::lround(peak_guess.x())), ay = int(std::lround(peak_guess.y()));
  // The region every candidate window can touch, with its integral image.
  int rx0 = INT32_MAX, ry0 = INT32_MAX, rx1 = INT32_MIN, ry1 = INT32_MIN;
  for (int hi = std::max(0, hc - 1); hi <= std::min(n_height_ - 1, hc + 1); ++hi)
    for (int oi = std::max(0, oc - 1); oi <= std::min(n_orient_ - 1, oc + 1); ++oi) {
      const Template& t = At(hi, oi);
      rx0 = std::min(rx0, ax + t.win_x0 - search_px), rx1 = std::max(rx1, ax + t.win_x1 + search_px + 1);
      ry0 = std::min(ry0, ay + t.win_y0 - search_px), ry1 = std::max(ry1, ay + t.win_y1 + search_px + 1);
    }
  rx0 = std::max(rx0, 0), ry0 = std::max(ry0, 0), rx1 = std::min(rx1, mask.width), ry1 = std::min(ry1, mask.height);
  if (rx1 <= rx0 || ry1 <= ry0) return best;
  const int W = rx1 - rx0 + 1;
  std::vector<int32_t> S(size_t(W) * (ry1 - ry0 + 1), 0);  // S(y, x): pixels in [rx0, rx0+x) x [ry0, ry0+y)
  for (int y = ry0; y < ry1; ++y) {
    int32_t row = 0;
    for (int x = rx0; x < rx1; ++x) {
      row += mask.At(x, y);
      S[size_t(y - ry0 + 1) * W + (x - rx0 + 1)] = S[size_t(y - ry0) * W + (x - rx0 + 1)] + row;
    }
  }
  // Pixels in [x0, x1] x [y0, y1] (image coordinates, clipped to the region).
  auto box = [&](int x0, int y0, int x1, int y1) -> double {
    x0 = std::max(x0, rx0) - rx0, y0 = std::max(y0, ry0) - ry0;
    x1 = std::min(x1 + 1, rx1) - rx0, y1 = std::min(y1 + 1, ry1) - ry0;
    if (x1 <= x0 || y1 <= y0) return 0.0;
    return double(S[size_t(y1) * W + x1] - S[size_t(y0) * W + x1] - S[size_t(y1) * W + x0] + S[size_t(y0) * W + x0]);
  };
  const int side = 2 * search_px + 1;
  std::vector<double> scores(size_t(side) * side), best_scores;
  for (int hi = std::max(0, hc - 1); hi <= std::min(n_height_ - 1, hc + 1); ++hi)
    for (int oi = std::max(0, oc - 1); oi <= std::min(n_orient_ - 1, oc + 1); ++oi) {
      const Template& t = At(hi, oi);
      const int rows = int(t.x0.size());
      const double n = double(t.win_y1 - t.win_y0 + 1) * (t.win_x1 - t.win_x0 + 1), st = t.count;
      const double var_t = st - st * st / n;
      bool improved = false;
      int best_dx = 0, best_dy = 0;
      for (int dy = -search_px; dy <= search_px; ++dy)
        for (int dx = -search_px; dx <= search_px; ++dx) {
          const int px = ax + dx, py = ay + dy;
          double sit = 0.0;
          for (int r = 0; r < rows; ++r)
            if (t.x1[size_t(r)] >= t.x0[size_t(r)])
              sit += box(px + t.x0[size_t(r)], py + t.row0 + r, px + t.x1[size_t(r)], py + t.row0 + r);
          const double si = box(px + t.win_x0, py + t.win_y0, px + t.win_x1, py + t.win_y1);
          const double den = std::sqrt(std::max(0.0, (si - si * si / n) * var_t));
          const double ncc = den > 0.0 ? (sit - si * st / n) / den : -1.0;
          scores[size_t(dy + search_px) * side + size_t(dx + search_px)] = ncc;
          if (ncc > best.score) best.score = ncc, best_dx = dx, best_dy = dy, improved = true;
        }
      if (!improved) continue;
      const Eigen::Vector2d d(std::cos((90.0 + (oi - n_orient_ / 2) * config_.orientation_step_deg) * kDeg),
                              std::sin((90.0 + (oi - n_orient_ / 2) * config_.orientation_step_deg) * kDeg));
      best.height_px = config_.min_height_px + hi * config_.height_step_px;
      best.orientation_rad = std::atan2(d.y(), d.x());
      auto at = [&](int dx, int dy) { return scores[size_t(dy + search_px) * side + size_t(dx + search_px)]; };
      Eigen::Vector2d frac = Eigen::Vector2d::Zero();
      if (std::abs(best_dx) < search_px) frac.x() = Vertex(at(best_dx - 1, best_dy), best.score, at(best_dx + 1, best_dy));
      if (std::abs(best_dy) < search_px) frac.y() = Vertex(at(best_dx, best_dy - 1), best.score, at(best_dx, best_dy + 1));
      best.peak_px = Eigen::Vector2d(ax + best_dx, ay + best_dy) + frac;
      best.base_px = best.peak_px + best.height_px * d;
      best.ok = true;
    }
  return best;
}

}  // namespace cone_tracker
