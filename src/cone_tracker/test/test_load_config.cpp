// LoadConfig against a parameter server, and a nodelet with a bad layout file
// (runs inside nodelet_bad_input.test, which provides the master).
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <diagnostic_msgs/DiagnosticStatus.h>

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
  EXPECT_EQ(c.segmenter.refinement, PeakRefinement::kTemplates);
  EXPECT_FALSE(c.segmenter.reject_bad_outline);
  EXPECT_EQ(c.layout_file, "/some/layout.yaml");
  EXPECT_EQ(c.fixed_frame, "site");
  EXPECT_NEAR(c.segmenter.hsi.hue_min_rad, 350.0 * M_PI / 180.0, 1e-12);
  EXPECT_NEAR(c.segmenter.hsi.hue_max_rad, 30.0 * M_PI / 180.0, 1e-12);
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
