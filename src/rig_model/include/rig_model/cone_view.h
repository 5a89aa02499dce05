// Which cones a camera pose puts "in plain view": the negative information of a per-cone
// association. A hypothesis (a camera pose that explains the detected cones) that also puts a layout
// cone in plain view where nothing was detected explains the image worse than one that does not, by
// the cost of a missed detection, -2 ln(1 - P_D) in chi-square units. After an outage a lone tall cone
// can often be read as a short cone nearer (the prior allows the shift); that reading usually moves
// the tall cone into the middle of the image, where the detector would have seen it. A cone the hypothesis puts
// only partly in view (cut by the image's edge, or overlapping another) is a miss too when the image has no orange
// where it would be; orange that a hypothesis puts no cone on is clutter, which it pays for too (UnexplainedOrange).
// The one rule cone_tracker's association and pose_ekf's lone-cone test share. ROS-free.
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

// A cone's silhouette as a triangle: its apex at the peak, its base through the base point, half_width_px to either
// side across the axis.
struct ConeSilhouette {
  Eigen::Vector2d peak_px = Eigen::Vector2d::Zero(), base_px = Eigen::Vector2d::Zero();
  double half_width_px = 0.0;
  ImageBox Box() const { return SilhouetteBox(peak_px, base_px, half_width_px); }
};

// What a detector cannot miss: the whole silhouette inside the image by margin_px on every side (the
// segmenter refuses blobs at the border, and a cut cone is no miss), at least min_height_px tall (small
// blobs fail its area gate), and apart from every other cone's silhouette (one cone may hide another,
// or the two merge into one blob that fits neither).
struct PlainViewRule {
  double margin_px = 8.0;
  double min_height_px = 12.0;
  // A cone only partly in view (not in plain view) is missed when at least part_min_area_px2 of its triangle lies
  // inside the image by margin_px, and less than part_max_orange_frac of that part lies in the orange regions (the
  // boxes around the mask's orange, every blob's, accepted or refused). Orange there may be it (cut by the image's
  // edge, refused, or partly hidden): no miss. A wrong reading puts the cone where the image shows none. The area
  // is a patch the mask cannot lose (the segmenter drops blobs under 4 px); a real cone, white bands and a few
  // pixels of prediction error included, leaves well over half its visible triangle orange.
  double part_min_area_px2 = 48.0;
  double part_max_orange_frac = 0.5;
  // An orange box within this of a cone's triangle is that cone's (UnexplainedOrange): a reading's pose is off by a
  // few pixels, and the boxes hold whole pixels.
  double explain_margin_px = 4.0;
};

// boxes: every layout cone's silhouette at the hypothesis's pose, nullopt for one not in front of
// the camera. Returns, per cone, whether it is in plain view in a width x height image.
std::vector<bool> InPlainView(const std::vector<std::optional<ImageBox>>& boxes, double width_px, double height_px,
                              const PlainViewRule& rule = {});

// The share of a silhouette's triangle inside the image by margin_px that lies in one of the `orange` boxes, sampled
// evenly over its area (78 points); *visible_px2 gets the area of that part (0: none, and the share is 0).
double OrangeShareInView(const ConeSilhouette& s, const std::vector<ImageBox>& orange, double width_px,
                         double height_px, double margin_px, double* visible_px2);

// The misses of a hypothesis: the layout cones that are not seen (seen[k]: a detection was taken as cone k) and that
// it puts in plain view (InPlainView), or partly in view where `orange` has none (PlainViewRule's part_*). Empty
// `orange`: not known (the image has at least the seen cone's), plain view only.
int MissedInView(const std::vector<std::optional<ConeSilhouette>>& silhouettes, const std::vector<bool>& seen,
                 const std::vector<ImageBox>& orange, double width_px, double height_px,
                 const PlainViewRule& rule = {});
// A measured cone's silhouette, for the orange it explains: a quarter of its height to either side, generous (a road
// cone's is a seventh from the side, more from above) so that its own orange is never left over.
ConeSilhouette DetectedSilhouette(const Eigen::Vector2d& peak_px, const Eigen::Vector2d& base_px);

// The converse: how many of the `orange` boxes lie near no cone's triangle, neither a layout cone's at the hypothesis's
// pose (`silhouettes`, seen or not) nor a detected cone's as measured (`detected`, the frame's cones, each explained in
// every reading, DetectedSilhouette): orange the hypothesis leaves to clutter. A reading that names a cut cone's
// neighbour, say, leaves the cut cone's orange at the image's edge unexplained, which the right one puts a layout cone
// on. A box on the edge of a width x height image reaches past it (the orange may go on outside, and a barrel lens
// shows what the pinhole image's bounds cut off); 0: unknown size.
int UnexplainedOrange(const std::vector<std::optional<ConeSilhouette>>& silhouettes,
                      const std::vector<ConeSilhouette>& detected, const std::vector<ImageBox>& orange, double width_px,
                      double height_px, const PlainViewRule& rule = {});

}  // namespace rig_model
