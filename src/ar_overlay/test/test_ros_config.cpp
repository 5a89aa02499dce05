// LoadConfig against a real parameter server (under rostest): defaults,
// values read, and each bad value refused with a message naming it.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include "ar_overlay/node/ros_config.h"

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

}  // namespace
}  // namespace ar_overlay

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_config");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
