// Which cones a camera pose puts "in plain view": the negative information of a per-cone
// association. A hypothesis (a camera pose that explains the detected cones) that also puts a layout
// cone in plain view where nothing was detected explains the image worse than one that does not, by
// the cost of a missed detection, -2 ln(1 - P_D) in chi-square units. After an outage a lone tall cone
// can often be read as a short cone nearer (the prior allows the shift); that reading usually moves
// the tall cone into the middle of the image, where the detector would have seen it. The one rule
// cone_tracker's association and pose_ekf's lone-cone test share. ROS-free.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

namespace rig_model {

// A cone's silhouette in pinhole pixels: the box around its peak and its base point, widened by the
// base's half-width on both sides.
struct ImageBox {
  double u_min = 0.0, v_min = 0.0, u_max = 0.0, v_max = 0.0;
  double height() const { return v_max - v_min; }
  bool Overlaps(const ImageBox& o) const {
    return u_min < o.u_max && o.u_min < u_max && v_min < o.v_max && o.v_min < v_max;
  }
};
ImageBox SilhouetteBox(const Eigen::Vector2d& peak_px, const Eigen::Vector2d& base_px, double half_width_px);

// What a detector cannot miss: the whole silhouette inside the image by margin_px on every side (the
// segmenter refuses blobs at the border, and a cut cone is no miss), at least min_height_px tall (small
// blobs fail its area gate), and apart from every other cone's silhouette (one cone may hide another,
// or the two merge into one blob that fits neither).
struct PlainViewRule {
  double margin_px = 8.0;
  double min_height_px = 12.0;
};

// boxes: every layout cone's silhouette at the hypothesis's pose, nullopt for one not in front of
// the camera. Returns, per cone, whether it is in plain view in a width x height image.
std::vector<bool> InPlainView(const std::vector<std::optional<ImageBox>>& boxes, double width_px, double height_px,
                              const PlainViewRule& rule = {});

// The misses of a hypothesis: the layout cones it puts in plain view (InPlainView) that are not seen (seen[k]: a
// detection was taken as cone k).
int MissedInPlainView(const std::vector<std::optional<ImageBox>>& boxes, const std::vector<bool>& seen, double width_px,
                      double height_px, const PlainViewRule& rule = {});

}  // namespace rig_model
