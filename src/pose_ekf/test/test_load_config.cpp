// pose_ekf's LoadConfig against a real parameter server (run by rostest): the shipped files load as
// the launch files load them, and a parameter the loader does not read is refused by name.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <fstream>

#include "pose_ekf/node/node_config.h"

namespace {

std::string RefusalOf(const ros::NodeHandle& pnh) {
  try {
    pose_ekf::LoadConfig(pnh);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(LoadConfig, ShippedFileLoadsAsTheLaunchFileLoadsIt) {
  EXPECT_EQ(RefusalOf(ros::NodeHandle("~shipped")), "");  // rosparam load + ~config_file, as pose_ekf.launch
}

TEST(LoadConfig, UnknownParameterIsRefusedWithTheNearestName) {
  ros::NodeHandle pnh("~misspelt");
  pnh.setParam("use_camera", true);
  pnh.setParam("sigma_gyr_rad_s", 0.01);
  EXPECT_EQ(RefusalOf(pnh), "parameter ~sigma_gyr_rad_s is unknown (did you mean ~sigma_gyro_rad_s?)");
}

TEST(LoadConfig, TheFileTheLaunchLoadedIsNamedWithTheLine) {
  const std::string path = ::testing::TempDir() + "pose_ekf_load_config_misspelt.yaml";
  std::ofstream(path) << "use_camera: true\nsigma_gyr_rad_s: 0.01\n";
  ros::NodeHandle pnh("~from_file");  // as `rosparam load` + pose_ekf.launch's config_file leave it
  pnh.setParam("use_camera", true);
  pnh.setParam("sigma_gyr_rad_s", 0.01);
  pnh.setParam("config_file", path);
  EXPECT_EQ(RefusalOf(pnh), path + ":2: unknown key 'sigma_gyr_rad_s' (did you mean 'sigma_gyro_rad_s'?)");

  // A clean file, and a misspelt parameter set elsewhere (a <param> line): the file is still named.
  std::ofstream(path) << "use_camera: true\n";
  ros::NodeHandle other("~set_elsewhere");
  other.setParam("config_file", path);
  other.setParam("use_acel", false);
  EXPECT_EQ(RefusalOf(other),
            "parameter ~use_acel is unknown (did you mean ~use_accel?) (parameters loaded from " + path + ")");
}

TEST(LoadConfig, WrongTypeIsRefusedByName) {
  ros::NodeHandle pnh("~wrong_type");
  pnh.setParam("sigma_gyro_rad_s", "fast");
  EXPECT_EQ(RefusalOf(pnh), "parameter ~sigma_gyro_rad_s must be a number");
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "pose_ekf_load_config_test");
  return RUN_ALL_TESTS();
}
