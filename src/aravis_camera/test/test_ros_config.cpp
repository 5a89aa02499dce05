// LoadConfig against a parameter server (its own master, no camera): the table covers every
// parameter, wrong types and misspelt names are refused naming them, the shipped launch file's
// parameters load, and the live settings round-trip through CameraLive.cfg by name.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include "aravis_camera/node/ros_config.h"
#include "rig_model/ros/launch_params.h"

namespace aravis_camera {
namespace {

std::string Error(const std::string& ns) {
  try {
    LoadConfig(ros::NodeHandle(ns));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(LoadConfig, ReadsEveryParameter) {
  ros::NodeHandle nh("~every");
  nh.setParam("camera_name", "127.0.0.1");
  nh.setParam("enable_fake_interface", true);
  nh.setParam("pixel_format", "RGB8");
  nh.setParam("width", 640);
  nh.setParam("height", 480);
  nh.setParam("offset_x", 8);
  nh.setParam("offset_y", 4);
  nh.setParam("frame_rate", 15);  // an integer where a double is wanted
  nh.setParam("exposure_auto", true);
  nh.setParam("exposure", 2000.0);
  nh.setParam("gain", 3.5);
  nh.setParam("packet_size", 1500);
  nh.setParam("inter_packet_delay", 100);
  nh.setParam("n_buffers", 12);
  nh.setParam("publish_incomplete", true);
  nh.setParam("reconnect_period", 1.5);
  nh.setParam("frame_timeout", 3.0);
  nh.setParam("stamp_source", "completion");
  nh.setParam("stamp_offset", 0.002);
  nh.setParam("frame_id", "cam");
  nh.setParam("camera_info_url", "file:///tmp/cam.yaml");
  nh.setParam("camera_info_name", "rig");
  EXPECT_EQ(Params().Names().size(), 22u);
  const NodeConfig n = LoadConfig(nh);
  const CameraConfig& c = n.camera;
  EXPECT_EQ(c.camera_name, "127.0.0.1");
  EXPECT_TRUE(c.enable_fake_interface);
  EXPECT_EQ(c.pixel_format, "RGB8");
  EXPECT_EQ(c.width_px, 640);
  EXPECT_EQ(c.height_px, 480);
  EXPECT_EQ(c.offset_x_px, 8);
  EXPECT_EQ(c.offset_y_px, 4);
  EXPECT_DOUBLE_EQ(c.frame_rate_hz, 15.0);
  EXPECT_TRUE(c.exposure_auto);
  EXPECT_DOUBLE_EQ(c.exposure_us, 2000.0);
  EXPECT_DOUBLE_EQ(c.gain_db, 3.5);
  EXPECT_EQ(c.packet_size_bytes, 1500);
  EXPECT_EQ(c.inter_packet_delay_ns, 100);
  EXPECT_EQ(c.n_buffers, 12);
  EXPECT_TRUE(c.publish_incomplete);
  EXPECT_DOUBLE_EQ(c.reconnect_period_s, 1.5);
  EXPECT_DOUBLE_EQ(c.frame_timeout_s, 3.0);
  EXPECT_EQ(c.stamp_source, StampSource::kCompletion);
  EXPECT_DOUBLE_EQ(c.stamp_offset_s, 0.002);
  EXPECT_EQ(c.frame_id, "cam");
  EXPECT_EQ(n.camera_info_url, "file:///tmp/cam.yaml");
  EXPECT_EQ(n.camera_info_name, "rig");
}

TEST(LoadConfig, DefaultsAreTheStructs) {
  const NodeConfig n = LoadConfig(ros::NodeHandle("~defaults"));
  EXPECT_EQ(n.camera.pixel_format, CameraConfig{}.pixel_format);
  EXPECT_EQ(n.camera.stamp_source, StampSource::kDevice);
  EXPECT_EQ(n.camera_info_name, "camera");
}

TEST(LoadConfig, RefusesAWrongTypeNamingIt) {
  ros::NodeHandle("~wrong_type").setParam("frame_rate", "fast");
  EXPECT_EQ(Error("~wrong_type"), "parameter ~frame_rate must be a number");
  ros::NodeHandle("~wrong_int").setParam("width", 640.5);
  EXPECT_EQ(Error("~wrong_int"), "parameter ~width must be an integer");
  ros::NodeHandle("~wrong_enum").setParam("stamp_source", "exposure");
  EXPECT_EQ(Error("~wrong_enum"), "parameter ~stamp_source must be one of device, host, completion (got 'exposure')");
}

TEST(LoadConfig, RefusesAMisspeltNameNamingTheNearest) {
  ros::NodeHandle("~misspelt").setParam("frame_rate_hz", 10.0);
  EXPECT_EQ(Error("~misspelt"), "parameter ~frame_rate_hz is unknown (did you mean ~frame_rate?)");
}

TEST(LoadConfig, RefusesAValueValidateRefuses) {
  ros::NodeHandle("~invalid").setParam("n_buffers", 0);
  EXPECT_NE(Error("~invalid").find("n_buffers"), std::string::npos) << Error("~invalid");
}

TEST(LoadConfig, EveryShippedLaunchParameterLoads) {
  const auto params =
      rig_model::LaunchParams(std::string(ARAVIS_CAMERA_DIR) + "/launch/camera.launch", "CameraNodelet");
  EXPECT_EQ(params.size(), 7u);
  rig_model::SetLaunchParams(ros::NodeHandle("~launch"), params);
  for (const auto& p : params) {
    EXPECT_TRUE(Params().Has(p.name)) << p.name;
    EXPECT_TRUE(p.resolved) << p.name;
  }
  EXPECT_EQ(Error("~launch"), "");
}

TEST(Reconfigure, LiveSettingsRoundTripThroughTheTable) {
  NodeConfig c;
  c.camera.frame_rate_hz = 12.5, c.camera.exposure_auto = true, c.camera.exposure_us = 3000.0;
  c.camera.gain_db = 6.0;
  const CameraLiveConfig live = ToLive(c);
  EXPECT_DOUBLE_EQ(live.frame_rate, 12.5);
  EXPECT_TRUE(live.exposure_auto);
  EXPECT_DOUBLE_EQ(live.exposure, 3000.0);
  EXPECT_DOUBLE_EQ(live.gain, 6.0);
  const NodeConfig back = FromLive(live, NodeConfig{});
  EXPECT_DOUBLE_EQ(back.camera.frame_rate_hz, 12.5);
  EXPECT_TRUE(back.camera.exposure_auto);
  EXPECT_DOUBLE_EQ(back.camera.exposure_us, 3000.0);
  EXPECT_DOUBLE_EQ(back.camera.gain_db, 6.0);
}

}  // namespace
}  // namespace aravis_camera

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ros_config");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
