// Template matching (3.1.5.4): binary triangles, a perfect silhouette of the
// cone, precomputed at start-up for every height x orientation of a grid (the
// thesis: 3 px of height, 3 degrees of orientation). A cone's line-search
// estimate picks the nine templates around it (one grid step of height and/or
// orientation), each scored at every apex offset within a search window by
// normalised cross-correlation with the binary mask; the best one gives the
// peak (its apex) and base (its base midpoint). ROS-free.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "cone_tracker/vision/blobs.h"

namespace cone_tracker {

struct TemplateSetConfig {
  double min_height_px = 12.0;
  double max_height_px = 600.0;
  double height_step_px = 3.0;
  double orientation_step_deg = 3.0;
  double max_tilt_deg = 60.0;  // orientations within this of upright (peak above base)
  double tau = 1.0 / 7.0;      // base half-width / height of the triangle (3.1.4's cone)
};

struct TemplateMatch {
  bool ok = false;
  double score = -1.0;  // normalised cross-correlation in [-1, 1]
  double height_px = 0.0, orientation_rad = 0.0;  // of the axis from peak to base, against +u
  Eigen::Vector2d peak_px = Eigen::Vector2d::Zero(), base_px = Eigen::Vector2d::Zero();
};

class ConeTemplateSet {
 public:
  explicit ConeTemplateSet(const TemplateSetConfig& config = TemplateSetConfig());
  const TemplateSetConfig& config() const { return config_; }
  size_t size() const { return templates_.size(); }

  // peak/base_guess: the line search's ends (raw pixels). Tries apex offsets
  // of up to +-search_px around peak_guess (integer pixels, then a parabola
  // through the best score and its neighbours for the fraction).
  TemplateMatch Refine(const MaskView& mask, const Eigen::Vector2d& peak_guess, const Eigen::Vector2d& base_guess,
                       int search_px) const;

 private:
  struct Template {
    int row0 = 0;                // first row, relative to the apex pixel
    std::vector<int16_t> x0, x1;  // per row, the pixels inside (x1 < x0: none), relative to the apex
    int min_x = 0, max_x = 0;
    int win_x0 = 0, win_x1 = 0, win_y0 = 0, win_y1 = 0;  // the template image (inclusive), relative to the apex
    double count = 0;  // pixels inside
  };
  const Template& At(int h, int o) const { return templates_[size_t(h) * n_orient_ + size_t(o)]; }

  TemplateSetConfig config_;
  int n_height_ = 0, n_orient_ = 0;
  std::vector<Template> templates_;
};

}  // namespace cone_tracker
