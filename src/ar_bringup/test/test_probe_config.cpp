// The latency probe's parameters against a parameter server: every field through the table, a
// wrong type and a misspelt name refused naming them, and what pipeline.launch gives it.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include "ar_bringup/probe_config.h"
#include "rig_model/ros/launch_params.h"

namespace ar_bringup {
namespace {

std::string Error(const std::string& ns) {
  try {
    LoadProbeConfig(ros::NodeHandle(ns));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ProbeConfig, ReadsEveryParameter) {
  ros::NodeHandle nh("~every");
  nh.setParam("output_file", "/tmp/probe.json");
  nh.setParam("fixed_frame", "map");
  nh.setParam("camera_frame", "cam");
  EXPECT_EQ(ProbeParams().Names().size(), 3u);
  const ProbeConfig c = LoadProbeConfig(nh);
  EXPECT_EQ(c.output_file, "/tmp/probe.json");
  EXPECT_EQ(c.fixed_frame, "map");
  EXPECT_EQ(c.camera_frame, "cam");
  const ProbeConfig d = LoadProbeConfig(ros::NodeHandle("~defaults"));
  EXPECT_EQ(d.output_file, "");
  EXPECT_EQ(d.fixed_frame, "cones");
  EXPECT_EQ(d.camera_frame, "camera_optical");
}

TEST(ProbeConfig, RefusesAWrongTypeNamingIt) {
  ros::NodeHandle("~wrong_type").setParam("output_file", 3);
  EXPECT_EQ(Error("~wrong_type"), "parameter ~output_file must be a string");
}

TEST(ProbeConfig, RefusesAMisspeltNameNamingTheNearest) {
  ros::NodeHandle("~misspelt").setParam("output_fil", "/tmp/x.json");
  EXPECT_EQ(Error("~misspelt"), "parameter ~output_fil is unknown (did you mean ~output_file?)");
}

TEST(ProbeConfig, PipelineLaunchParametersLoad) {
  const auto params =
      rig_model::LaunchParams(std::string(AR_ROOT) + "/launch/include/pipeline.launch", "LatencyProbeNodelet");
  EXPECT_EQ(params.size(), 1u);
  for (const auto& p : params) EXPECT_TRUE(ProbeParams().Has(p.name)) << p.name;
  rig_model::SetLaunchParams(ros::NodeHandle("~launch"), params);
  EXPECT_EQ(Error("~launch"), "");
}

}  // namespace
}  // namespace ar_bringup

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_probe_config");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
