// cone_tracker's parameter table (no master): it covers every parameter the nodelet has read, the
// .cfg's names are all in it and a config survives the round trip through dynamic_reconfigure, and
// a YAML file with the same names (detect_cones) reads the same way, strictly.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include <yaml-cpp/yaml.h>

#include "cone_tracker/ConeTrackerConfig.h"
#include "cone_tracker/node/params.h"
#include "rig_model/ros/param_table_ros.h"
#include "rig_model/strict_yaml.h"
#include "test_files.h"

namespace cone_tracker {
namespace {

// The names LoadConfig read one by one before the table (and the nodelet's README lists).
const std::set<std::string> kLoadConfigNames = {"layout_file",
                                                "fixed_frame",
                                                "camera_frame",
                                                "use_tf_prediction",
                                                "prediction_max_age_s",
                                                "reacquire_after_s",
                                                "heading_prior_deg",
                                                "two_cone_gravity_sigma_deg",
                                                "gravity_window_s",
                                                "prediction_sigma_m",
                                                "prediction_sigma_deg",
                                                "prediction_drift_m_s",
                                                "prediction_max_sigma_m",
                                                "association_margin",
                                                "association_miss_cost",
                                                "association_unexplained_cost",
                                                "expected_rate_hz",
                                                "rate_tolerance",
                                                "hue_min_deg",
                                                "hue_max_deg",
                                                "sat_min",
                                                "sat_max",
                                                "val_min",
                                                "val_max",
                                                "pyramid_levels",
                                                "roi_margin_px",
                                                "min_fragment_area_px",
                                                "merge_lateral_frac",
                                                "merge_gap_frac",
                                                "min_area_px",
                                                "max_area_px",
                                                "border_px",
                                                "min_solidity",
                                                "max_solidity",
                                                "min_axis_ratio",
                                                "max_axis_ratio",
                                                "max_tilt_deg",
                                                "line_search_misses",
                                                "peak_refinement",
                                                "reject_bad_outline",
                                                "split_merged_tips",
                                                "read_collars",
                                                "template_search_px",
                                                "outline_outlier_px",
                                                "outline_max_edge_rms_px",
                                                "colour_model",
                                                "merge_band_gap_frac",
                                                "cut_cone_contrast",
                                                "verify_cone_shape",
                                                "shape_min_height_px",
                                                "shape_max_top_width_frac",
                                                "shape_max_width_rms_frac",
                                                "shape_max_hole_frac",
                                                "detector",
                                                "dnn_model",
                                                "dnn_score_min",
                                                "dnn_min_colour_frac",
                                                "sigma_px",
                                                "max_assignment_px",
                                                "chi2_probability",
                                                "max_translation_change_m",
                                                "max_rotation_change_deg",
                                                "debug_tint_mask",
                                                "debug_draw_rejected",
                                                "debug_draw_text"};

TEST(NodeParams, CoverEveryParameterLoadConfigRead) {
  const std::vector<std::string> names = NodeParams().Names();
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()), kLoadConfigNames);
  EXPECT_EQ(names.size(), kLoadConfigNames.size());  // no name twice
}

TEST(NodeParams, ReconfigureRoundTripIsTheIdentity) {
  NodeConfig c;  // every .cfg parameter away from its default, inside the .cfg's range
  SegmenterConfig& s = c.segmenter;
  s.hsi.hue_min_deg = 350.5, s.hsi.hue_max_deg = 25.25, s.hsi.sat_min = 0.45, s.hsi.sat_max = 0.95;
  s.hsi.val_min = 0.15, s.hsi.val_max = 0.9;
  s.min_area_px = 20.0, s.max_area_px = 9000.0, s.border_px = 6, s.min_solidity = 0.7, s.max_solidity = 0.98;
  s.cut_cone_contrast = 25;
  s.min_axis_ratio = 1.1, s.max_axis_ratio = 6.5, s.max_tilt_deg = 40.0, s.merge_lateral_frac = 0.3;
  s.merge_gap_frac = 0.7, s.peak_refinement = int(PeakRefinement::kTemplates), s.reject_bad_outline = false;
  s.split_merged_tips = false, s.read_collars = false;
  c.pose.sigma_px = 1.5, c.pose.max_assignment_px = 25.0, c.pose.chi2_probability = 0.99;
  c.pose.max_translation_change_m = 0.4, c.pose.max_rotation_change_deg = 20.0;
  c.debug = DebugImageConfig{false, false, false};

  const ConeTrackerConfig r = rig_model::ToReconfigure<NodeConfig, ConeTrackerConfig>(NodeParams(), c);
  EXPECT_EQ(r.hue_min_deg, 350.5);  // the same unit on both sides: no conversion
  EXPECT_EQ(r.peak_refinement, 1);
  EXPECT_EQ(r.border_px, 6);
  EXPECT_FALSE(r.debug_draw_text);

  NodeConfig back;
  rig_model::FromReconfigure(NodeParams(), r, &back);
  dynamic_reconfigure::Config msg;
  r.__toMessage__(msg);
  int compared = 0;
  rig_model::ReadReconfigureMessage(msg, [&](const std::string& name, const rig_model::ParamValue&) {
    EXPECT_EQ(NodeParams().Get(back, name), NodeParams().Get(c, name)) << name;
    EXPECT_NE(NodeParams().Get(NodeConfig(), name), NodeParams().Get(c, name)) << name << " left at its default";
    ++compared;
  });
  EXPECT_EQ(compared, 29);  // every parameter of cfg/ConeTracker.cfg
}

TEST(NodeParams, YamlReadsTheSameNamesStrictly) {
  const rig_model::StrictReader reader("tracker.yaml");
  NodeConfig c;
  NodeParams().FromYaml(YAML::Load("hue_min_deg: 340\nhue_max_deg: 30.5\nborder_px: 0\npeak_refinement: none\n"
                                   "reject_bad_outline: false\nfixed_frame: site\nheading_prior_deg: .nan\n"),
                        reader, "", &c);
  EXPECT_EQ(c.segmenter.hsi.hue_min_deg, 340.0);
  EXPECT_EQ(c.segmenter.hsi.hue_max_deg, 30.5);
  EXPECT_EQ(c.segmenter.border_px, 0);
  EXPECT_EQ(c.segmenter.refinement(), PeakRefinement::kNone);
  EXPECT_FALSE(c.segmenter.reject_bad_outline);
  EXPECT_EQ(c.fixed_frame, "site");

  // The silhouette gate's bounds, and a bound out of range refused naming the parameter.
  NodeParams().FromYaml(YAML::Load("shape_min_height_px: 14\nshape_max_top_width_frac: 0.5\n"
                                   "shape_max_width_rms_frac: 0.2\nshape_max_hole_frac: 0.3\n"),
                        reader, "", &c);
  EXPECT_EQ(c.segmenter.shape.min_height_px, 14.0);
  EXPECT_EQ(c.segmenter.shape.max_top_width_frac, 0.5);
  EXPECT_EQ(c.segmenter.shape.max_width_rms_frac, 0.2);
  EXPECT_EQ(c.segmenter.shape.max_hole_frac, 0.3);
  EXPECT_EQ(c.segmenter.Validate(), "");
  c.segmenter.shape.max_hole_frac = 1.5;
  EXPECT_EQ(c.segmenter.Validate(), "shape_max_hole_frac must be in [0, 1]");

  // The old detect_cones names in radians are refused, pointing at the parameter's name.
  EXPECT_EQ(ErrorOf([&] { NodeParams().FromYaml(YAML::Load("hue_min_rad: 5.9\n"), reader, "", &c); }),
            "tracker.yaml:1: unknown key 'hue_min_rad' (did you mean 'hue_min_deg'?)");
  EXPECT_EQ(ErrorOf([&] { NodeParams().FromYaml(YAML::Load("sat_min: 0.5\nborder_px: 2.5\n"), reader, "", &c); }),
            "tracker.yaml:2: border_px: must be an integer");
  EXPECT_EQ(ErrorOf([&] { NodeParams().FromYaml(YAML::Load("peak_refinement: best\n"), reader, "", &c); }),
            "tracker.yaml:1: peak_refinement: must be one of outline, templates, none (got 'best')");
  EXPECT_EQ(ErrorOf([&] { NodeParams().FromYaml(YAML::Load("debug_tint_mask: 3\n"), reader, "", &c); }),
            "tracker.yaml:1: debug_tint_mask: must be true or false");
}

}  // namespace
}  // namespace cone_tracker
