#include "cone_tracker/node/node_config.h"

#include <ros/node_handle.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "rig_model/ros/params.h"

namespace cone_tracker {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// The private node handle, recording every name LoadConfig reads: those are the known names, so a
// parameter added to LoadConfig is known without a second list.
struct Params {
  const ros::NodeHandle& nh;
  std::vector<std::string>* read;
};

// Absent: the struct's default stays; a wrong type throws naming the parameter (rig_model).
template <typename T>
void Get(const Params& p, const std::string& name, T* value) {
  p.read->push_back(name);
  rig_model::GetParam(p.nh, name, value);
}

void Check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("parameter ~" + what);
}

}  // namespace

void ValidateConfig(const NodeConfig& c) {
  Check(!c.fixed_frame.empty(), "fixed_frame must not be empty");
  Check(!c.camera_frame.empty(), "camera_frame must not be empty");
  Check(c.prediction_max_age_s >= 0.0, "prediction_max_age_s must be >= 0");
  Check(c.reacquire_after_s > 0.0, "reacquire_after_s must be > 0");
  Check(std::isnan(c.heading_prior_deg) || std::isfinite(c.heading_prior_deg),
        "heading_prior_deg must be finite or nan");
  Check(c.expected_rate_hz > 0.0, "expected_rate_hz must be > 0");
  Check(c.rate_tolerance >= 0.0 && c.rate_tolerance < 1.0, "rate_tolerance must be in [0, 1)");
  const std::string seg = c.segmenter.Validate();
  Check(seg.empty(), seg);
  const std::string pose = c.pose.Validate();
  Check(pose.empty(), pose);
}

NodeConfig LoadConfig(const ros::NodeHandle& private_nh) {
  std::vector<std::string> read;
  const Params nh{private_nh, &read};
  NodeConfig c;
  Get(nh, "layout_file", &c.layout_file);
  Get(nh, "fixed_frame", &c.fixed_frame);
  Get(nh, "camera_frame", &c.camera_frame);
  Get(nh, "use_tf_prediction", &c.use_tf_prediction);
  Get(nh, "prediction_max_age_s", &c.prediction_max_age_s);
  Get(nh, "reacquire_after_s", &c.reacquire_after_s);
  Get(nh, "heading_prior_deg", &c.heading_prior_deg);
  Get(nh, "expected_rate_hz", &c.expected_rate_hz);
  Get(nh, "rate_tolerance", &c.rate_tolerance);

  SegmenterConfig& s = c.segmenter;
  double hue_min_deg = s.hsi.hue_min_rad / kDegToRad, hue_max_deg = s.hsi.hue_max_rad / kDegToRad;
  Get(nh, "hue_min_deg", &hue_min_deg);
  Get(nh, "hue_max_deg", &hue_max_deg);
  s.hsi.hue_min_rad = hue_min_deg * kDegToRad;
  s.hsi.hue_max_rad = hue_max_deg * kDegToRad;
  Get(nh, "sat_min", &s.hsi.sat_min);
  Get(nh, "sat_max", &s.hsi.sat_max);
  Get(nh, "val_min", &s.hsi.val_min);
  Get(nh, "val_max", &s.hsi.val_max);
  Get(nh, "pyramid_levels", &s.pyramid_levels);
  Get(nh, "roi_margin_px", &s.roi_margin_px);
  Get(nh, "min_fragment_area_px", &s.min_fragment_area_px);
  Get(nh, "merge_lateral_frac", &s.merge_lateral_frac);
  Get(nh, "merge_gap_frac", &s.merge_gap_frac);
  Get(nh, "min_area_px", &s.min_area_px);
  Get(nh, "max_area_px", &s.max_area_px);
  Get(nh, "border_px", &s.border_px);
  Get(nh, "min_solidity", &s.min_solidity);
  Get(nh, "max_solidity", &s.max_solidity);
  Get(nh, "min_axis_ratio", &s.min_axis_ratio);
  Get(nh, "max_axis_ratio", &s.max_axis_ratio);
  Get(nh, "max_tilt_deg", &s.max_tilt_deg);
  Get(nh, "line_search_misses", &s.line_search_misses);
  // A name or, as dynamic_reconfigure leaves it on the server for the next start, the .cfg enum's int.
  std::vector<std::string> refinements;
  for (PeakRefinement r : {PeakRefinement::kOutline, PeakRefinement::kTemplates, PeakRefinement::kNone}) {
    refinements.push_back(PeakRefinementName(r));
  }
  int refinement = static_cast<int>(s.refinement);
  nh.read->push_back("peak_refinement");
  rig_model::GetEnumParam(nh.nh, "peak_refinement", refinements, &refinement);
  s.refinement = static_cast<PeakRefinement>(refinement);  // the enum's values are the .cfg's (segmenter.h)
  Get(nh, "reject_bad_outline", &s.reject_bad_outline);
  Get(nh, "template_search_px", &s.template_search_px);
  Get(nh, "outline_outlier_px", &s.outline.outlier_px);
  Get(nh, "outline_max_edge_rms_px", &s.outline.max_edge_rms_px);

  ConePoseConfig& p = c.pose;
  Get(nh, "sigma_px", &p.sigma_px);
  Get(nh, "max_assignment_px", &p.max_assignment_px);
  Get(nh, "chi2_probability", &p.chi2_probability);
  Get(nh, "max_translation_change_m", &p.max_translation_change_m);
  Get(nh, "max_rotation_change_deg", &p.max_rotation_change_deg);
  p.initial_heading_rad = c.heading_prior_deg * kDegToRad;

  Get(nh, "debug_tint_mask", &c.debug.tint_mask);
  Get(nh, "debug_draw_rejected", &c.debug.draw_rejected);
  Get(nh, "debug_draw_text", &c.debug.draw_text);

  // Also known: diagnostic_updater's period and the debug image's image_transport plugin settings
  // (compressed_image_transport keeps ~debug_image/compressed/* on the server across restarts).
  read.insert(read.end(), {"diagnostic_period", "debug_image"});
  rig_model::CheckParamNames(private_nh, read);
  Check(!c.layout_file.empty(),
        "layout_file is required (a layout YAML in rig_model's schema, e.g. "
        "$(find rig_model)/config/layouts/default.yaml)");
  ValidateConfig(c);
  return c;
}

}  // namespace cone_tracker
