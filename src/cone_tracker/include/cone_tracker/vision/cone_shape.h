// Verification of a blob's silhouette against a cone's (not in the thesis, whose gates 3.1.5.3 pass
// orange signs, barrier planks and hi-vis clothing in real scenes): seen from the side a cone's
// width grows linearly from the peak down to the base, the peak is above the base, and its outline
// has no holes. A rectangle's width does not taper, a lettered sign has holes. ROS-free.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "cone_tracker/vision/blobs.h"

namespace cone_tracker {

struct ConeShapeConfig {
  bool enabled = true;
  double min_height_px = 10.0;       // shorter blobs are not judged (too few rows to say)
  double max_top_width_frac = 0.6;   // line-fitted width at the peak / at the base
  double max_width_rms_frac = 0.25;  // RMS of the width about that line / base width
  double max_hole_frac = 0.2;        // non-blob pixels inside the rows' extents / those extents
};

struct ConeShapeCheck {
  bool ok = true;
  std::string why;  // when !ok
  double top_width_frac = 0.0, width_rms_frac = 0.0, hole_frac = 0.0;
};

// Judges the blob's runs between peak and base (image pixels, the line search's or the outline's).
ConeShapeCheck CheckConeShape(const std::vector<Run>& runs, const Eigen::Vector2d& peak_px,
                              const Eigen::Vector2d& base_px, const ConeShapeConfig& config);

}  // namespace cone_tracker
