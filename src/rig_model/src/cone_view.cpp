#include "rig_model/cone_view.h"

#include <algorithm>

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

int MissedInPlainView(const std::vector<std::optional<ImageBox>>& boxes, const std::vector<bool>& seen, double width_px,
                      double height_px, const PlainViewRule& rule) {
  const std::vector<bool> plain = InPlainView(boxes, width_px, height_px, rule);
  int missed = 0;
  for (size_t k = 0; k < plain.size(); ++k) missed += plain[k] && !(k < seen.size() && seen[k]);
  return missed;
}

}  // namespace rig_model
