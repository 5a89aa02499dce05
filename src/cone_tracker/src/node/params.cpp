#include "cone_tracker/node/params.h"

#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include "rig_model/strict_yaml.h"

namespace cone_tracker {
namespace {

using Table = rig_model::ParamTable<NodeConfig>;

std::vector<std::string> PeakRefinementNames() {
  std::vector<std::string> names;
  for (int i = 0; i < kPeakRefinements; ++i) names.push_back(PeakRefinementName(static_cast<PeakRefinement>(i)));
  return names;
}

std::vector<std::string> DetectorKindNames() {
  std::vector<std::string> names;
  for (int i = 0; i < kDetectorKinds; ++i) names.push_back(DetectorKindName(static_cast<DetectorKind>(i)));
  return names;
}

Table MakeTable() {
  return Table()
      .Add("layout_file", [](NodeConfig& c) -> std::string& { return c.layout_file; })
      .Add("fixed_frame", [](NodeConfig& c) -> std::string& { return c.fixed_frame; })
      .Add("camera_frame", [](NodeConfig& c) -> std::string& { return c.camera_frame; })
      .Add("use_tf_prediction", [](NodeConfig& c) -> bool& { return c.use_tf_prediction; })
      .Add("prediction_max_age_s", [](NodeConfig& c) -> double& { return c.prediction_max_age_s; })
      .Add("reacquire_after_s", [](NodeConfig& c) -> double& { return c.reacquire_after_s; })
      .Add("heading_prior_deg", [](NodeConfig& c) -> double& { return c.heading_prior_deg; })
      .Add("two_cone_gravity_sigma_deg", [](NodeConfig& c) -> double& { return c.two_cone_gravity_sigma_deg; })
      .Add("gravity_window_s", [](NodeConfig& c) -> double& { return c.gravity_window_s; })
      .Add("prediction_sigma_m", [](NodeConfig& c) -> double& { return c.prediction_sigma_m; })
      .Add("prediction_sigma_deg", [](NodeConfig& c) -> double& { return c.prediction_sigma_deg; })
      .Add("prediction_drift_m_s", [](NodeConfig& c) -> double& { return c.prediction_drift_m_s; })
      .Add("prediction_max_sigma_m", [](NodeConfig& c) -> double& { return c.prediction_max_sigma_m; })
      .Add("association_margin", [](NodeConfig& c) -> double& { return c.association_margin; })
      .Add("association_miss_cost", [](NodeConfig& c) -> double& { return c.association_miss_cost; })
      .Add("association_unexplained_cost", [](NodeConfig& c) -> double& { return c.association_unexplained_cost; })
      .Add("expected_rate_hz", [](NodeConfig& c) -> double& { return c.expected_rate_hz; })
      .Add("rate_tolerance", [](NodeConfig& c) -> double& { return c.rate_tolerance; })
      // Segmentation (3.1.5): the HSI bounds (3.22), the ROI, the blob gates and the peak/base.
      .Add("hue_min_deg", [](NodeConfig& c) -> double& { return c.segmenter.hsi.hue_min_deg; })
      .Add("hue_max_deg", [](NodeConfig& c) -> double& { return c.segmenter.hsi.hue_max_deg; })
      .Add("sat_min", [](NodeConfig& c) -> double& { return c.segmenter.hsi.sat_min; })
      .Add("sat_max", [](NodeConfig& c) -> double& { return c.segmenter.hsi.sat_max; })
      .Add("val_min", [](NodeConfig& c) -> double& { return c.segmenter.hsi.val_min; })
      .Add("val_max", [](NodeConfig& c) -> double& { return c.segmenter.hsi.val_max; })
      .Add("pyramid_levels", [](NodeConfig& c) -> int& { return c.segmenter.pyramid_levels; })
      .Add("roi_margin_px", [](NodeConfig& c) -> int& { return c.segmenter.roi_margin_px; })
      .Add("min_fragment_area_px", [](NodeConfig& c) -> int& { return c.segmenter.min_fragment_area_px; })
      .Add("merge_lateral_frac", [](NodeConfig& c) -> double& { return c.segmenter.merge_lateral_frac; })
      .Add("merge_gap_frac", [](NodeConfig& c) -> double& { return c.segmenter.merge_gap_frac; })
      .Add("min_area_px", [](NodeConfig& c) -> double& { return c.segmenter.min_area_px; })
      .Add("max_area_px", [](NodeConfig& c) -> double& { return c.segmenter.max_area_px; })
      .Add("border_px", [](NodeConfig& c) -> int& { return c.segmenter.border_px; })
      .Add("min_solidity", [](NodeConfig& c) -> double& { return c.segmenter.min_solidity; })
      .Add("max_solidity", [](NodeConfig& c) -> double& { return c.segmenter.max_solidity; })
      .Add("min_axis_ratio", [](NodeConfig& c) -> double& { return c.segmenter.min_axis_ratio; })
      .Add("max_axis_ratio", [](NodeConfig& c) -> double& { return c.segmenter.max_axis_ratio; })
      .Add("max_tilt_deg", [](NodeConfig& c) -> double& { return c.segmenter.max_tilt_deg; })
      .Add("line_search_misses", [](NodeConfig& c) -> int& { return c.segmenter.line_search_misses; })
      .AddEnum(
          "peak_refinement", [](NodeConfig& c) -> int& { return c.segmenter.peak_refinement; }, PeakRefinementNames())
      .Add("reject_bad_outline", [](NodeConfig& c) -> bool& { return c.segmenter.reject_bad_outline; })
      .Add("split_merged_tips", [](NodeConfig& c) -> bool& { return c.segmenter.split_merged_tips; })
      .Add("read_collars", [](NodeConfig& c) -> bool& { return c.segmenter.read_collars; })
      .Add("template_search_px", [](NodeConfig& c) -> double& { return c.segmenter.template_search_px; })
      .Add("outline_outlier_px", [](NodeConfig& c) -> double& { return c.segmenter.outline.outlier_px; })
      .Add("outline_max_edge_rms_px", [](NodeConfig& c) -> double& { return c.segmenter.outline.max_edge_rms_px; })
      // The learned colour table and the cone-silhouette check (not in the thesis).
      .Add("colour_model", [](NodeConfig& c) -> std::string& { return c.segmenter.colour_model; })
      .Add("merge_band_gap_frac", [](NodeConfig& c) -> double& { return c.segmenter.merge_band_gap_frac; })
      .Add("cut_cone_contrast", [](NodeConfig& c) -> int& { return c.segmenter.cut_cone_contrast; })
      .Add("verify_cone_shape", [](NodeConfig& c) -> bool& { return c.segmenter.shape.enabled; })
      .Add("shape_min_height_px", [](NodeConfig& c) -> double& { return c.segmenter.shape.min_height_px; })
      .Add("shape_max_top_width_frac", [](NodeConfig& c) -> double& { return c.segmenter.shape.max_top_width_frac; })
      .Add("shape_max_width_rms_frac", [](NodeConfig& c) -> double& { return c.segmenter.shape.max_width_rms_frac; })
      .Add("shape_max_hole_frac", [](NodeConfig& c) -> double& { return c.segmenter.shape.max_hole_frac; })
      // The detector: colour segmentation, or the learned detector for photos (vision/cone_detector.h).
      .AddEnum(
          "detector", [](NodeConfig& c) -> int& { return c.detector.detector; }, DetectorKindNames())
      .Add("dnn_model", [](NodeConfig& c) -> std::string& { return c.detector.dnn_model; })
      .Add("dnn_score_min", [](NodeConfig& c) -> double& { return c.detector.dnn_score_min; })
      .Add("dnn_min_colour_frac", [](NodeConfig& c) -> double& { return c.detector.dnn_min_colour_frac; })
      // Correspondence and the gates (3.1.6, 6.4).
      .Add("sigma_px", [](NodeConfig& c) -> double& { return c.pose.sigma_px; })
      .Add("max_assignment_px", [](NodeConfig& c) -> double& { return c.pose.max_assignment_px; })
      .Add("chi2_probability", [](NodeConfig& c) -> double& { return c.pose.chi2_probability; })
      .Add("max_translation_change_m", [](NodeConfig& c) -> double& { return c.pose.max_translation_change_m; })
      .Add("max_rotation_change_deg", [](NodeConfig& c) -> double& { return c.pose.max_rotation_change_deg; })
      // The debug image.
      .Add("debug_tint_mask", [](NodeConfig& c) -> bool& { return c.debug.tint_mask; })
      .Add("debug_draw_rejected", [](NodeConfig& c) -> bool& { return c.debug.draw_rejected; })
      .Add("debug_draw_text", [](NodeConfig& c) -> bool& { return c.debug.draw_text; });
}

}  // namespace

const rig_model::ParamTable<NodeConfig>& NodeParams() {
  static const Table table = MakeTable();
  return table;
}

NodeConfig LoadConfigFile(const std::string& path) {
  const rig_model::StrictReader reader(path);
  const YAML::Node root = rig_model::LoadYamlFile(path);
  NodeConfig c;
  if (root.IsNull()) return c;  // comments only: the defaults
  const auto& table = NodeParams();
  table.FromYaml(root, reader, "", &c);
  for (const auto& kv : root) {
    const rig_model::ParamValue v = table.Get(c, kv.first.Scalar());
    const double* d = std::get_if<double>(&v);
    if (d && !std::isfinite(*d) && kv.first.Scalar() != "heading_prior_deg") {
      reader.Fail(kv.second, kv.first.Scalar(), "must be finite");
    }
  }
  std::string& model = c.segmenter.colour_model;
  const size_t slash = path.find_last_of('/');
  if (!model.empty() && model[0] != '/' && slash != std::string::npos) model = path.substr(0, slash + 1) + model;
  return c;
}

}  // namespace cone_tracker
