// pose_ekf's LoadConfig against a real parameter server (run by rostest): the shipped files load as
// the launch files load them, and a parameter the loader does not read is refused by name.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <fstream>

#include "pose_ekf/node/node_config.h"
#include "rig_model/ros/param_table_ros.h"

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

// Every name of the table set on the server (none at its default, each with the type ROS gives it)
// comes back in its field.
TEST(LoadConfig, EveryParameterComesBackThroughTheServer) {
  pose_ekf::NodeConfig set;
  set.cones_frame = "map";
  set.publish_tf = false;
  set.output_rate_hz = 40.0;
  set.config_file = "";  // empty: no file to check
  set.use_accel = false;
  set.accel_mode = 1;
  set.quat_integration = 1;
  set.ekf.sigma_gyro_rad_s = 0.02;
  set.ekf.reinit_after_rejections = 9;
  set.ekf.estimate_gyro_bias = true;
  set.ekf.max_predict_step_s = 0.01;
  ros::NodeHandle pnh("~every");
  for (const std::string& name : pose_ekf::ParamNames()) {
    const rig_model::ParamValue v = pose_ekf::Params().Get(set, name);
    if (const auto* d = std::get_if<double>(&v)) pnh.setParam(name, *d);
    if (const auto* i = std::get_if<int>(&v)) pnh.setParam(name, *i);
    if (const auto* b = std::get_if<bool>(&v)) pnh.setParam(name, *b);
    if (const auto* s = std::get_if<std::string>(&v)) pnh.setParam(name, *s);
  }
  pnh.setParam("accel_mode", "orientation");  // enums as the YAML files write them
  pose_ekf::NodeConfig got;
  ASSERT_NO_THROW(got = pose_ekf::LoadConfig(pnh));
  for (const std::string& name : pose_ekf::ParamNames()) {
    EXPECT_EQ(pose_ekf::Params().Get(got, name), pose_ekf::Params().Get(set, name)) << name;
  }
  EXPECT_EQ(got.ekf.accel_mode, pose_ekf::AccelMode::kOff);  // use_accel false
  EXPECT_EQ(got.ekf.quat_integration, pose_ekf::QuatIntegration::kExact);
}

TEST(LoadConfig, WrongEnumIsRefusedByName) {
  ros::NodeHandle pnh("~wrong_enum");
  pnh.setParam("accel_mode", "sideways");
  EXPECT_EQ(RefusalOf(pnh),
            "parameter ~accel_mode must be one of off, orientation, position_orientation (got 'sideways')");
  ros::NodeHandle note("~wrong_note");
  note.setParam("config_file", 3);
  EXPECT_EQ(RefusalOf(note), "parameter ~config_file must be a string");
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "pose_ekf_load_config_test");
  return RUN_ALL_TESTS();
}
