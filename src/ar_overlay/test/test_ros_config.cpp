// LoadConfig against a real parameter server (under rostest): defaults,
// values read, and each bad value refused with a message naming it.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include "ar_overlay/node/ros_config.h"
#include "rig_model/ros/launch_params.h"

namespace ar_overlay {
namespace {

std::string Load(const std::string& ns, OverlayConfig& c) { return LoadConfig(ros::NodeHandle(ns), c); }

TEST(LoadConfig, DefaultsAreValid) {
  OverlayConfig c;
  EXPECT_EQ(Load("~defaults", c), "");
  EXPECT_EQ(c.fixed_frame, "cones");
  EXPECT_EQ(c.pose_mode, PoseMode::kImageStamp);
  EXPECT_DOUBLE_EQ(c.render_rate_hz, 40.0);
}

TEST(LoadConfig, ReadsValues) {
  ros::NodeHandle nh("~good");
  nh.setParam("pose_mode", "predicted");
  nh.setParam("render_rate_hz", 30.0);
  nh.setParam("show_window", true);
  OverlayConfig c;
  EXPECT_EQ(Load("~good", c), "");
  EXPECT_EQ(c.pose_mode, PoseMode::kPredicted);
  EXPECT_DOUBLE_EQ(c.render_rate_hz, 30.0);
  EXPECT_TRUE(c.show_window);
}

TEST(LoadConfig, RefusesBadValuesNamingThem) {
  const std::vector<std::pair<std::string, XmlRpc::XmlRpcValue>> bad = {
      {"pose_mode", XmlRpc::XmlRpcValue("latest")},      {"render_rate_hz", XmlRpc::XmlRpcValue(0.0)},
      {"tf_timeout_s", XmlRpc::XmlRpcValue(-1.0)},       {"near_m", XmlRpc::XmlRpcValue(0.0)},
      {"scene_yaml", XmlRpc::XmlRpcValue("/nope.yaml")}, {"fixed_frame", XmlRpc::XmlRpcValue("")},
      {"max_prediction_s", XmlRpc::XmlRpcValue(5.0)},    {"lod_max_error_px", XmlRpc::XmlRpcValue(-1.0)},
  };
  int i = 0;
  for (const auto& [name, value] : bad) {
    const std::string ns = "~bad" + std::to_string(i++);
    ros::NodeHandle(ns).setParam(name, value);
    OverlayConfig c;
    const std::string error = Load(ns, c);
    EXPECT_NE(error.find(name), std::string::npos) << name << ": '" << error << "'";
  }
}

TEST(LoadConfig, RefusesAWrongTypeNamingIt) {
  ros::NodeHandle("~wrong_type").setParam("render_rate_hz", "fast");
  OverlayConfig c;
  EXPECT_EQ(Load("~wrong_type", c), "parameter ~render_rate_hz must be a number");
  ros::NodeHandle("~wrong_type_bool").setParam("show_window", 1);
  EXPECT_EQ(Load("~wrong_type_bool", c), "parameter ~show_window must be true or false");
}

TEST(LoadConfig, RefusesAMisspeltNameNamingTheNearest) {
  ros::NodeHandle("~misspelt").setParam("render_rate", 30.0);
  OverlayConfig c;
  EXPECT_EQ(Load("~misspelt", c), "parameter ~render_rate is unknown (did you mean ~render_rate_hz?)");
}

TEST(LoadConfig, TheTableCoversEveryField) {
  ros::NodeHandle nh("~every");
  nh.setParam("scene_yaml", std::string(AR_OVERLAY_DIR) + "/config/scene_peaks.yaml");
  nh.setParam("fixed_frame", "map");
  nh.setParam("camera_frame", "cam");
  nh.setParam("pose_mode", 1);  // an enum's index, as dynamic_reconfigure writes it
  nh.setParam("tf_timeout_s", 0.2);
  nh.setParam("render_rate_hz", 50.0);
  nh.setParam("display_latency_s", 0.01);
  nh.setParam("max_prediction_s", 0.2);
  nh.setParam("velocity_window_s", 0.05);
  nh.setParam("near_m", 0.1);
  nh.setParam("far_m", 100.0);
  nh.setParam("lod_max_error_px", 2);  // an integer where a double is wanted
  nh.setParam("show_window", true);
  nh.setParam("window_name", "lcd");
  EXPECT_EQ(Params().Names().size(), 14u);
  OverlayConfig c;
  ASSERT_EQ(Load("~every", c), "");
  EXPECT_EQ(c.scene_yaml, std::string(AR_OVERLAY_DIR) + "/config/scene_peaks.yaml");
  EXPECT_EQ(c.fixed_frame, "map");
  EXPECT_EQ(c.camera_frame, "cam");
  EXPECT_EQ(c.pose_mode, PoseMode::kPredicted);
  EXPECT_DOUBLE_EQ(c.tf_timeout_s, 0.2);
  EXPECT_DOUBLE_EQ(c.render_rate_hz, 50.0);
  EXPECT_DOUBLE_EQ(c.display_latency_s, 0.01);
  EXPECT_DOUBLE_EQ(c.max_prediction_s, 0.2);
  EXPECT_DOUBLE_EQ(c.velocity_window_s, 0.05);
  EXPECT_DOUBLE_EQ(c.near_m, 0.1);
  EXPECT_DOUBLE_EQ(c.far_m, 100.0);
  EXPECT_DOUBLE_EQ(c.lod_max_error_px, 2.0);
  EXPECT_TRUE(c.show_window);
  EXPECT_EQ(c.window_name, "lcd");
}

TEST(LoadConfig, EveryShippedLaunchParameterLoads) {
  int i = 0;
  for (const std::string file : {"overlay.launch", "overlay_platform.launch"}) {
    const auto params = rig_model::LaunchParams(std::string(AR_OVERLAY_DIR) + "/launch/" + file, "OverlayNodelet");
    EXPECT_FALSE(params.empty()) << file;
    const std::string ns = "~launch" + std::to_string(i++);
    rig_model::SetLaunchParams(ros::NodeHandle(ns), params);  // all but the $(find ...) paths
    for (const auto& p : params) EXPECT_TRUE(Params().Has(p.name)) << file << ": " << p.name;
    OverlayConfig c;
    EXPECT_EQ(Load(ns, c), "") << file;
  }
}

}  // namespace
}  // namespace ar_overlay

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_config");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
