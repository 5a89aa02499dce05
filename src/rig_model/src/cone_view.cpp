#include "rig_model/cone_view.h"

#include <algorithm>
#include <cmath>

namespace rig_model {

ImageBox SilhouetteBox(const Eigen::Vector2d& peak_px, const Eigen::Vector2d& base_px, double half_width_px) {
  ImageBox b;
  b.u_min = std::min(peak_px.x(), base_px.x()) - half_width_px;
  b.u_max = std::max(peak_px.x(), base_px.x()) + half_width_px;
  b.v_min = std::min(peak_px.y(), base_px.y());
  b.v_max = std::max(peak_px.y(), base_px.y());
  return b;
}

std::vector<bool> InPlainView(const std::vector<std::optional<ImageBox>>& boxes, double width_px, double height_px,
                              const PlainViewRule& rule) {
  std::vector<bool> plain(boxes.size(), false);
  const double m = rule.margin_px;
  for (size_t i = 0; i < boxes.size(); ++i) {
    if (!boxes[i]) continue;
    const ImageBox& b = *boxes[i];
    if (!(b.u_min >= m && b.v_min >= m && b.u_max <= width_px - 1.0 - m && b.v_max <= height_px - 1.0 - m)) continue;
    if (!(b.height() >= rule.min_height_px)) continue;
    bool apart = true;
    for (size_t j = 0; j < boxes.size() && apart; ++j) apart = j == i || !boxes[j] || !b.Overlaps(*boxes[j]);
    plain[i] = apart;
  }
  return plain;
}

double OrangeShareInView(const ConeSilhouette& s, const std::vector<ImageBox>& orange, double width_px,
                         double height_px, double margin_px, double* visible_px2) {
  // Rows at the centres of kRows equal steps from the apex to the base, row r with r + 1 points evenly across:
  // a row's width grows with its distance from the apex, so the points are spread evenly over the area.
  constexpr int kRows = 12;
  const Eigen::Vector2d axis = s.base_px - s.peak_px;
  const double length = axis.norm();
  Eigen::Vector2d across(1.0, 0.0);
  if (length > 0.0) across = Eigen::Vector2d(-axis.y(), axis.x()) / length;
  const double lo = margin_px, u_hi = width_px - 1.0 - margin_px, v_hi = height_px - 1.0 - margin_px;
  int total = 0, visible = 0, covered = 0;
  for (int r = 0; r < kRows; ++r) {
    const double f = (r + 0.5) / kRows;
    for (int j = 0; j <= r; ++j) {
      const double t = ((j + 0.5) / (r + 1) - 0.5) * 2.0 * f * s.half_width_px;
      const Eigen::Vector2d p = s.peak_px + f * axis + t * across;
      ++total;
      if (!(p.x() >= lo && p.y() >= lo && p.x() <= u_hi && p.y() <= v_hi)) continue;
      ++visible;
      for (const ImageBox& b : orange)
        if (p.x() >= b.u_min && p.x() <= b.u_max && p.y() >= b.v_min && p.y() <= b.v_max) {
          ++covered;
          break;
        }
    }
  }
  *visible_px2 = length * s.half_width_px * visible / total;  // the triangle's area, length * half-width
  return visible > 0 ? double(covered) / visible : 0.0;
}

int MissedInView(const std::vector<std::optional<ConeSilhouette>>& silhouettes, const std::vector<bool>& seen,
                 const std::vector<ImageBox>& orange, double width_px, double height_px, const PlainViewRule& rule) {
  std::vector<std::optional<ImageBox>> boxes(silhouettes.size());
  for (size_t k = 0; k < silhouettes.size(); ++k)
    if (silhouettes[k]) boxes[k] = silhouettes[k]->Box();
  const std::vector<bool> plain = InPlainView(boxes, width_px, height_px, rule);
  int missed = 0;
  for (size_t k = 0; k < plain.size(); ++k) {
    if (!silhouettes[k] || (k < seen.size() && seen[k])) continue;
    if (plain[k]) {
      ++missed;
    } else if (!orange.empty()) {
      // The visible triangle lies (near enough: an upright one exactly) in the visible part of its box: a cone wholly
      // outside the image, or too little in it, is not sampled. A large layout's association asks this of every cone
      // for every assignment; the shortcut can only leave out a miss, never add one.
      const ImageBox& box = *boxes[k];
      const double m = rule.margin_px;
      const double du = std::min(box.u_max, width_px - 1.0 - m) - std::max(box.u_min, m);
      const double dv = std::min(box.v_max, height_px - 1.0 - m) - std::max(box.v_min, m);
      if (!(du > 0.0 && dv > 0.0 && du * dv >= rule.part_min_area_px2)) continue;
      double visible_px2 = 0.0;
      const double share =
          OrangeShareInView(*silhouettes[k], orange, width_px, height_px, rule.margin_px, &visible_px2);
      missed += visible_px2 >= rule.part_min_area_px2 && share < rule.part_max_orange_frac;
    }
  }
  return missed;
}

namespace {

// Whether the triangle of s, grown by margin_px, and the box overlap: no axis among the box's two and the triangle's
// three edge normals separates them (the separating-axis test for convex polygons).
bool TriangleOverlapsBox(const ConeSilhouette& s, const ImageBox& b, double margin_px) {
  const Eigen::Vector2d axis = s.base_px - s.peak_px;
  const double length = axis.norm();
  const Eigen::Vector2d across = length > 0.0 ? Eigen::Vector2d(-axis.y(), axis.x()) / length : Eigen::Vector2d(1, 0);
  const Eigen::Vector2d tri[3] = {s.peak_px, s.base_px + s.half_width_px * across,
                                  s.base_px - s.half_width_px * across};
  const Eigen::Vector2d box[4] = {{b.u_min, b.v_min}, {b.u_max, b.v_min}, {b.u_max, b.v_max}, {b.u_min, b.v_max}};
  const auto separated = [&](const Eigen::Vector2d& n) {
    const double norm = n.norm();
    if (!(norm > 0.0)) return false;
    double t_lo = INFINITY, t_hi = -INFINITY, b_lo = INFINITY, b_hi = -INFINITY;
    for (const Eigen::Vector2d& p : tri) t_lo = std::min(t_lo, p.dot(n) / norm), t_hi = std::max(t_hi, p.dot(n) / norm);
    for (const Eigen::Vector2d& p : box) b_lo = std::min(b_lo, p.dot(n) / norm), b_hi = std::max(b_hi, p.dot(n) / norm);
    return t_hi + margin_px < b_lo || b_hi + margin_px < t_lo;
  };
  if (separated({1.0, 0.0}) || separated({0.0, 1.0})) return false;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d e = tri[(i + 1) % 3] - tri[i];
    if (separated({-e.y(), e.x()})) return false;
  }
  return true;
}

}  // namespace

ConeSilhouette DetectedSilhouette(const Eigen::Vector2d& peak_px, const Eigen::Vector2d& base_px) {
  return {peak_px, base_px, 0.25 * (base_px - peak_px).norm()};
}

int UnexplainedOrange(const std::vector<std::optional<ConeSilhouette>>& silhouettes,
                      const std::vector<ConeSilhouette>& detected, const std::vector<ImageBox>& orange, double width_px,
                      double height_px, const PlainViewRule& rule) {
  const double m = rule.explain_margin_px, far = 1e6;
  int unexplained = 0;
  for (ImageBox b : orange) {
    if (width_px > 0.0 && height_px > 0.0) {  // on the edge: reaching past it (the pixels' outer edges at -0.5)
      if (b.u_min <= 0.0) b.u_min = -far;
      if (b.v_min <= 0.0) b.v_min = -far;
      if (b.u_max >= width_px - 1.0) b.u_max = far;
      if (b.v_max >= height_px - 1.0) b.v_max = far;
    }
    const ImageBox grown{b.u_min - m, b.v_min - m, b.u_max + m, b.v_max + m};
    const auto near = [&](const ConeSilhouette& s) { return s.Box().Overlaps(grown) && TriangleOverlapsBox(s, b, m); };
    bool explained = std::any_of(detected.begin(), detected.end(), near);
    for (size_t k = 0; k < silhouettes.size() && !explained; ++k) explained = silhouettes[k] && near(*silhouettes[k]);
    unexplained += !explained;
  }
  return unexplained;
}

}  // namespace rig_model
