// LoadParams and CheckParamNames against a parameter server: nested names, names the component
// reads itself (also_known), and the errors that name the parameter.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include "rig_model/ros/param_table_ros.h"

namespace rig_model {
namespace {

struct Config {
  double rate_hz = 100.0;
  double window_s = 10.0;
  std::string port = "/dev/ttyUSB0";
};

const ParamTable<Config>& Table() {
  static const ParamTable<Config> table =
      ParamTable<Config>()
          .Add("rate_hz", [](Config& c) -> double& { return c.rate_hz; })
          .Add("time_sync/window_s", [](Config& c) -> double& { return c.window_s; })
          .Add("port", [](Config& c) -> std::string& { return c.port; });
  return table;
}

std::string Error(const std::string& ns, const std::vector<std::string>& also_known = {}) {
  Config c;
  try {
    LoadParams(ros::NodeHandle(ns), Table(), &c, also_known);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(LoadParams, ReadsNestedNames) {
  ros::NodeHandle nh("~nested");
  nh.setParam("time_sync/window_s", 20.0);
  nh.setParam("rate_hz", 50);
  Config c;
  LoadParams(nh, Table(), &c);
  EXPECT_DOUBLE_EQ(c.window_s, 20.0);
  EXPECT_DOUBLE_EQ(c.rate_hz, 50.0);
}

TEST(LoadParams, RefusesAMisspeltNestedNameByItsFullName) {
  ros::NodeHandle("~nested_typo").setParam("time_sync/windw_s", 20.0);
  EXPECT_EQ(Error("~nested_typo"), "parameter ~time_sync/windw_s is unknown (did you mean ~time_sync/window_s?)");
}

TEST(LoadParams, RefusesAWrongTypeInANestedName) {
  ros::NodeHandle("~nested_type").setParam("time_sync/window_s", "long");
  EXPECT_EQ(Error("~nested_type"), "parameter ~time_sync/window_s must be a number");
}

TEST(LoadParams, AcceptsNamesTheComponentReadsItself) {
  ros::NodeHandle nh("~also");
  nh.setParam("gyro_bias_rad_s", std::vector<double>{0.0, 0.0, 0.0});
  nh.setParam("camera_imu/rotation_xyzw", std::vector<double>{0.0, 0.0, 0.0, 1.0});
  EXPECT_EQ(Error("~also", {"gyro_bias_rad_s", "camera_imu/rotation_xyzw"}), "");
  EXPECT_EQ(Error("~also", {"gyro_bias_rad_s"}), "parameter ~camera_imu is unknown");
  nh.setParam("gyro_bias_rads", std::vector<double>{0.0, 0.0, 0.0});
  EXPECT_EQ(Error("~also", {"gyro_bias_rad_s", "camera_imu/rotation_xyzw"}),
            "parameter ~gyro_bias_rads is unknown (did you mean ~gyro_bias_rad_s?)");
}

TEST(LoadParams, AKnownNamespaceCoversItsNames) {
  ros::NodeHandle("~namespace").setParam("debug_image/compressed/format", "png");
  EXPECT_EQ(Error("~namespace", {"debug_image"}), "");
}

}  // namespace
}  // namespace rig_model

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_load_params");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
