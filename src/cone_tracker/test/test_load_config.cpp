// LoadConfig against a parameter server, and a nodelet with a bad layout file
// (runs inside nodelet_bad_input.test, which provides the master).
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <dynamic_reconfigure/server.h>

#include "cone_tracker/ConeTrackerConfig.h"

#include "cone_tracker/node/node_config.h"
#include "nodelet_test_util.h"

namespace cone_tracker {
namespace {

std::string LoadError(const std::function<void(ros::NodeHandle&)>& set) {
  ros::NodeHandle nh("~bad_config");
  nh.deleteParam("");
  nh.setParam("layout_file", "/some/layout.yaml");
  set(nh);
  try {
    LoadConfig(nh);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(LoadConfig, ReadsEveryGroupWithUnits) {
  ros::NodeHandle nh("~config");
  nh.setParam("layout_file", "/some/layout.yaml");
  nh.setParam("fixed_frame", "site");
  nh.setParam("hue_min_deg", 350.0);
  nh.setParam("hue_max_deg", 30);  // an int for a double parameter is fine
  nh.setParam("min_area_px", 12.0);
  nh.setParam("border_px", 2);
  nh.setParam("chi2_probability", 0.99);
  nh.setParam("max_rotation_change_deg", 10.0);
  nh.setParam("heading_prior_deg", 45.0);
  nh.setParam("use_tf_prediction", false);
  nh.setParam("debug_draw_text", false);
  nh.setParam("peak_refinement", "templates");
  nh.setParam("reject_bad_outline", false);
  const NodeConfig c = LoadConfig(nh);
  EXPECT_EQ(c.segmenter.refinement(), PeakRefinement::kTemplates);
  EXPECT_FALSE(c.segmenter.reject_bad_outline);
  EXPECT_EQ(c.layout_file, "/some/layout.yaml");
  EXPECT_EQ(c.fixed_frame, "site");
  EXPECT_EQ(c.segmenter.hsi.hue_min_deg, 350.0);  // degrees in the struct too (the colour table converts)
  EXPECT_EQ(c.segmenter.hsi.hue_max_deg, 30.0);
  EXPECT_EQ(c.segmenter.min_area_px, 12.0);
  EXPECT_EQ(c.segmenter.border_px, 2);
  EXPECT_EQ(c.pose.chi2_probability, 0.99);
  EXPECT_EQ(c.pose.max_rotation_change_deg, 10.0);
  EXPECT_NEAR(c.pose.initial_heading_rad, M_PI / 4.0, 1e-12);
  EXPECT_FALSE(c.use_tf_prediction);
  EXPECT_FALSE(c.debug.draw_text);
  EXPECT_TRUE(c.debug.tint_mask);
}

TEST(LoadConfig, RefusesBadValuesNamingTheParameter) {
  EXPECT_NE(LoadError([](ros::NodeHandle& nh) { nh.deleteParam("layout_file"); }).find("layout_file is required"),
            std::string::npos);
  EXPECT_NE(LoadError([](ros::NodeHandle& nh) { nh.setParam("min_area_px", "big"); }).find("~min_area_px"),
            std::string::npos);
  EXPECT_NE(LoadError([](ros::NodeHandle& nh) { nh.setParam("border_px", 2.5); }).find("~border_px"),
            std::string::npos);
  EXPECT_NE(LoadError([](ros::NodeHandle& nh) {
              nh.setParam("sat_min", 0.9);
              nh.setParam("sat_max", 0.2);
            }).find("sat"),
            std::string::npos);
  EXPECT_NE(LoadError([](ros::NodeHandle& nh) { nh.setParam("chi2_probability", 1.0); }).find("chi2_probability"),
            std::string::npos);
  EXPECT_NE(LoadError([](ros::NodeHandle& nh) { nh.setParam("fixed_frame", ""); }).find("fixed_frame"),
            std::string::npos);
  EXPECT_NE(LoadError([](ros::NodeHandle& nh) { nh.setParam("expected_rate_hz", -1.0); }).find("expected_rate_hz"),
            std::string::npos);
  EXPECT_NE(LoadError([](ros::NodeHandle& nh) { nh.setParam("peak_refinement", "best"); }).find("peak_refinement"),
            std::string::npos);
  EXPECT_EQ(LoadError([](ros::NodeHandle& nh) { nh.setParam("heading_prior_deg", "nan"); }), "");
}

TEST(LoadConfig, RefusesAnUnknownParameterWithTheNearestName) {
  // A tracker_config YAML (pipeline.launch) with a typo: refused, not silently left at the default.
  EXPECT_EQ(LoadError([](ros::NodeHandle& nh) { nh.setParam("sat_mni", 0.5); }),
            "parameter ~sat_mni is unknown (did you mean ~sat_min?)");
  EXPECT_EQ(LoadError([](ros::NodeHandle& nh) { nh.setParam("diagnostic_period", 0.1); }), "");
}

// A restart on a running master (issue 17.6): the nodelet's dynamic_reconfigure server wrote every
// tunable back under ~, enums as ints; the next LoadConfig must read exactly that.
TEST(LoadConfig, ReadsBackWhatDynamicReconfigureLeft) {
  ros::NodeHandle nh("~restart");
  nh.deleteParam("");
  nh.setParam("layout_file", "/some/layout.yaml");
  ConeTrackerConfig written = ConeTrackerConfig::__getDefault__();
  written.peak_refinement = 1;  // templates
  written.border_px = 7;
  written.sat_min = 0.4;
  written.reject_bad_outline = false;
  {
    boost::recursive_mutex mutex;
    dynamic_reconfigure::Server<ConeTrackerConfig> server(mutex, nh);
    server.updateConfig(written);
  }
  XmlRpc::XmlRpcValue left;
  ASSERT_TRUE(nh.getParam("peak_refinement", left));
  EXPECT_EQ(left.getType(), XmlRpc::XmlRpcValue::TypeInt);  // why LoadConfig must take the int
  NodeConfig c;
  ASSERT_NO_THROW(c = LoadConfig(nh));
  EXPECT_EQ(c.segmenter.refinement(), PeakRefinement::kTemplates);
  EXPECT_EQ(c.segmenter.border_px, 7);
  EXPECT_DOUBLE_EQ(c.segmenter.hsi.sat_min, 0.4);
  EXPECT_FALSE(c.segmenter.reject_bad_outline);
  EXPECT_DOUBLE_EQ(c.segmenter.hsi.hue_max_deg, written.hue_max_deg);
  EXPECT_DOUBLE_EQ(c.pose.sigma_px, written.sigma_px);
}

TEST(LoadConfig, PeakRefinementTakesTheNameOrTheCfgInt) {
  const auto load = [](const XmlRpc::XmlRpcValue& value) {
    ros::NodeHandle nh("~refinement");
    nh.deleteParam("");
    nh.setParam("layout_file", "/some/layout.yaml");
    nh.setParam("peak_refinement", value);
    return LoadConfig(nh).segmenter.refinement();
  };
  EXPECT_EQ(load(XmlRpc::XmlRpcValue(0)), PeakRefinement::kOutline);
  EXPECT_EQ(load(XmlRpc::XmlRpcValue(2)), PeakRefinement::kNone);
  EXPECT_EQ(load(XmlRpc::XmlRpcValue("templates")), PeakRefinement::kTemplates);
  for (const std::function<void(ros::NodeHandle&)>& bad :
       {std::function<void(ros::NodeHandle&)>([](ros::NodeHandle& nh) { nh.setParam("peak_refinement", 3); }),
        std::function<void(ros::NodeHandle&)>([](ros::NodeHandle& nh) { nh.setParam("peak_refinement", -1); }),
        std::function<void(ros::NodeHandle&)>([](ros::NodeHandle& nh) { nh.setParam("peak_refinement", 1.0); }),
        std::function<void(ros::NodeHandle&)>([](ros::NodeHandle& nh) { nh.setParam("peak_refinement", "1"); })}) {
    const std::string error = LoadError(bad);
    EXPECT_NE(error.find("parameter ~peak_refinement must be one of outline, templates, none"), std::string::npos)
        << error;
  }
}

// Every parameter the nodelet reads, each set to a value other than its default, reaches its own
// field (the names are the ones LoadConfig read before the parameter table; issue 17.2).
TEST(LoadConfig, EveryParameterReachesItsField) {
  ros::NodeHandle nh("~every");
  nh.deleteParam("");
  nh.setParam("layout_file", "/some/layout.yaml");
  nh.setParam("fixed_frame", "site");
  nh.setParam("camera_frame", "cam");
  nh.setParam("use_tf_prediction", false);
  nh.setParam("prediction_max_age_s", 0.25);
  nh.setParam("reacquire_after_s", 2.0);
  nh.setParam("heading_prior_deg", 90.0);
  nh.setParam("expected_rate_hz", 20.0);
  nh.setParam("rate_tolerance", 0.3);
  nh.setParam("hue_min_deg", 10.0);
  nh.setParam("hue_max_deg", 35.0);
  nh.setParam("sat_min", 0.4);
  nh.setParam("sat_max", 0.9);
  nh.setParam("val_min", 0.3);
  nh.setParam("val_max", 0.95);
  nh.setParam("pyramid_levels", 1);
  nh.setParam("roi_margin_px", 5);
  nh.setParam("min_fragment_area_px", 6);
  nh.setParam("merge_lateral_frac", 0.2);
  nh.setParam("merge_gap_frac", 0.4);
  nh.setParam("min_area_px", 25.0);
  nh.setParam("max_area_px", 1000.0);
  nh.setParam("border_px", 3);
  nh.setParam("min_solidity", 0.7);
  nh.setParam("max_solidity", 0.99);
  nh.setParam("min_axis_ratio", 1.2);
  nh.setParam("max_axis_ratio", 7.0);
  nh.setParam("max_tilt_deg", 45.0);
  nh.setParam("line_search_misses", 4);
  nh.setParam("peak_refinement", "none");
  nh.setParam("reject_bad_outline", false);
  nh.setParam("template_search_px", 3.0);
  nh.setParam("outline_outlier_px", 1.5);
  nh.setParam("outline_max_edge_rms_px", 0.7);
  nh.setParam("sigma_px", 2.0);
  nh.setParam("max_assignment_px", 20.0);
  nh.setParam("chi2_probability", 0.99);
  nh.setParam("max_translation_change_m", 0.3);
  nh.setParam("max_rotation_change_deg", 20.0);
  nh.setParam("debug_tint_mask", false);
  nh.setParam("debug_draw_rejected", false);
  nh.setParam("debug_draw_text", false);
  NodeConfig c;
  ASSERT_NO_THROW(c = LoadConfig(nh));
  EXPECT_EQ(c.layout_file, "/some/layout.yaml");
  EXPECT_EQ(c.fixed_frame, "site");
  EXPECT_EQ(c.camera_frame, "cam");
  EXPECT_FALSE(c.use_tf_prediction);
  EXPECT_EQ(c.prediction_max_age_s, 0.25);
  EXPECT_EQ(c.reacquire_after_s, 2.0);
  EXPECT_EQ(c.heading_prior_deg, 90.0);
  EXPECT_NEAR(c.pose.initial_heading_rad, M_PI / 2.0, 1e-12);
  EXPECT_EQ(c.expected_rate_hz, 20.0);
  EXPECT_EQ(c.rate_tolerance, 0.3);
  const SegmenterConfig& s = c.segmenter;
  EXPECT_EQ(s.hsi.hue_min_deg, 10.0);
  EXPECT_EQ(s.hsi.hue_max_deg, 35.0);
  EXPECT_EQ(s.hsi.sat_min, 0.4);
  EXPECT_EQ(s.hsi.sat_max, 0.9);
  EXPECT_EQ(s.hsi.val_min, 0.3);
  EXPECT_EQ(s.hsi.val_max, 0.95);
  EXPECT_EQ(s.pyramid_levels, 1);
  EXPECT_EQ(s.roi_margin_px, 5);
  EXPECT_EQ(s.min_fragment_area_px, 6);
  EXPECT_EQ(s.merge_lateral_frac, 0.2);
  EXPECT_EQ(s.merge_gap_frac, 0.4);
  EXPECT_EQ(s.min_area_px, 25.0);
  EXPECT_EQ(s.max_area_px, 1000.0);
  EXPECT_EQ(s.border_px, 3);
  EXPECT_EQ(s.min_solidity, 0.7);
  EXPECT_EQ(s.max_solidity, 0.99);
  EXPECT_EQ(s.min_axis_ratio, 1.2);
  EXPECT_EQ(s.max_axis_ratio, 7.0);
  EXPECT_EQ(s.max_tilt_deg, 45.0);
  EXPECT_EQ(s.line_search_misses, 4);
  EXPECT_EQ(s.refinement(), PeakRefinement::kNone);
  EXPECT_FALSE(s.reject_bad_outline);
  EXPECT_EQ(s.template_search_px, 3.0);
  EXPECT_EQ(s.outline.outlier_px, 1.5);
  EXPECT_EQ(s.outline.max_edge_rms_px, 0.7);
  EXPECT_EQ(c.pose.sigma_px, 2.0);
  EXPECT_EQ(c.pose.max_assignment_px, 20.0);
  EXPECT_EQ(c.pose.chi2_probability, 0.99);
  EXPECT_EQ(c.pose.max_translation_change_m, 0.3);
  EXPECT_EQ(c.pose.max_rotation_change_deg, 20.0);
  EXPECT_FALSE(c.debug.tint_mask);
  EXPECT_FALSE(c.debug.draw_rejected);
  EXPECT_FALSE(c.debug.draw_text);
}

TEST(LoadConfig, ImageTransportSettingsUnderDebugImageAreKnown) {
  EXPECT_EQ(LoadError([](ros::NodeHandle& nh) { nh.setParam("debug_image/compressed/jpeg_quality", 80); }), "");
  EXPECT_EQ(LoadError([](ros::NodeHandle& nh) { nh.setParam("debug_imag", 1); }),
            "parameter ~debug_imag is unknown (did you mean ~debug_image?)");
}

TEST(BadLayout, TheNodeletReportsTheFileAndField) {
  NodeletRig rig;
  const std::string name = "cone_tracker_bad_layout: tracker";
  ASSERT_TRUE(SpinUntil([&] { return rig.statuses.count(name) > 0; }, 30.0)) << "no diagnostics from the nodelet";
  const TrackerStatus& s = rig.statuses[name];
  EXPECT_EQ(s.level, diagnostic_msgs::DiagnosticStatus::ERROR);
  EXPECT_NE(s.message.find("typo.yaml"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("typo.yaml:5: cones[1].height_m: must be a number"), std::string::npos) << s.message;
}

}  // namespace cone_tracker
