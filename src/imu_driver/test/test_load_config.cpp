// LoadConfig against a real parameter server (run by rostest): values arrive,
// bad ones are refused with the parameter's name.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <fstream>
#include "imu_driver/node/ros_adapter.h"
#include "rig_model/ros/launch_params.h"

namespace imu_driver {
namespace {

std::string RefusalOf(const ros::NodeHandle& pnh) {
  try {
    LoadConfig(pnh);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(LoadConfig, DefaultsAndValues) {
  ros::NodeHandle pnh("~defaults");
  const DriverConfig d = LoadConfig(pnh);
  EXPECT_EQ(d.reader.port, "/dev/ttyUSB0");
  EXPECT_EQ(d.reader.baud, 115200);
  EXPECT_EQ(d.frame_id, "imu");
  EXPECT_FALSE(d.gyro_bias_calibrated);
  EXPECT_FALSE(d.publish_in_camera_frame);

  ros::NodeHandle set("~set");
  set.setParam("port", "/dev/ttyS3");
  set.setParam("baud", 57600);
  set.setParam("frame_id", "crista");
  set.setParam("time_source", "pps");
  set.setParam("gyro_bias_rad_s", std::vector<double>{0.1, 0.2, 0.3});
  set.setParam("publish_in_camera_frame", true);
  set.setParam("camera_imu/rotation_xyzw", std::vector<double>{0.0, 0.0, 0.7071068, 0.7071068});
  const DriverConfig c = LoadConfig(set);
  EXPECT_EQ(c.reader.port, "/dev/ttyS3");
  EXPECT_EQ(c.reader.baud, 57600);
  EXPECT_EQ(c.frame_id, "crista");
  EXPECT_EQ(c.reader.stream.time_source, StreamConfig::TimeSource::kPps);
  EXPECT_TRUE(c.gyro_bias_calibrated);
  EXPECT_DOUBLE_EQ(c.gyro_bias_rad_s(2), 0.3);
  EXPECT_NEAR(c.q_camera_imu.w(), std::sqrt(0.5), 1e-6);
}

TEST(LoadConfig, BadValuesAreRefusedByName) {
  ros::NodeHandle a("~bad_baud");
  a.setParam("baud", 12345);
  EXPECT_NE(RefusalOf(a).find("bad_baud/baud"), std::string::npos) << RefusalOf(a);
  ros::NodeHandle b("~bad_sigma");
  b.setParam("gyro_noise_sigma_rad_s", std::vector<double>{0.1, -0.2, 0.3});
  EXPECT_NE(RefusalOf(b).find("gyro_noise_sigma_rad_s"), std::string::npos);
  ros::NodeHandle c("~bad_rate");
  c.setParam("rate_hz", 0.0);
  EXPECT_NE(RefusalOf(c).find("rate_hz"), std::string::npos);
  ros::NodeHandle d("~camera_without_rotation");
  d.setParam("publish_in_camera_frame", true);
  EXPECT_NE(RefusalOf(d).find("camera_imu/rotation_xyzw"), std::string::npos);
  ros::NodeHandle e("~bad_source");
  e.setParam("time_source", "gps");
  EXPECT_NE(RefusalOf(e).find("time_source"), std::string::npos);
}

TEST(LoadConfig, ShippedFilesLoadAsTheLaunchFileLoadsThem) {
  const DriverConfig c = LoadConfig(ros::NodeHandle("~shipped"));  // load_config.test: as imu_driver.launch
  EXPECT_FALSE(c.gyro_bias_calibrated);
  EXPECT_DOUBLE_EQ(c.q_camera_imu.w(), 1.0);
}

TEST(LoadConfig, UnknownParameterIsRefusedWithTheNearestName) {
  ros::NodeHandle a("~misspelt");
  a.setParam("rate_hzz", 100.0);
  EXPECT_EQ(RefusalOf(a), "parameter ~rate_hzz is unknown (did you mean ~rate_hz?)");
  ros::NodeHandle b("~misspelt_nested");
  b.setParam("time_sync/slack_pmm", 20.0);
  EXPECT_EQ(RefusalOf(b), "parameter ~time_sync/slack_pmm is unknown (did you mean ~time_sync/slack_ppm?)");
}

TEST(LoadConfig, TheConfigFileTheLaunchLoadedIsNamed) {
  const std::string path = ::testing::TempDir() + "imu_driver_load_config_misspelt.yaml";
  std::ofstream(path) << "port: /dev/ttyS1\ntime_sync:\n  window_s: 1.0\n  slack_pmm: 20.0\n";
  ros::NodeHandle a("~from_file");  // as rosparam load + imu_driver.launch's config_file leave it
  a.setParam("time_sync/slack_pmm", 20.0);
  a.setParam("config_file", path);
  EXPECT_EQ(RefusalOf(a), path + ":4: unknown key 'time_sync.slack_pmm' (did you mean 'slack_ppm'?)");
  std::ofstream(path) << "port: /dev/ttyS1\n";
  ros::NodeHandle b("~set_elsewhere");
  b.setParam("config_file", path);
  b.setParam("bauds", 9600);
  EXPECT_EQ(RefusalOf(b), "parameter ~bauds is unknown (did you mean ~baud?) (parameters loaded from " + path + ")");
}

TEST(LoadConfig, CalibrationFilesThatCannotBeUsedAreRefusedByName) {
  const std::string zero = ::testing::TempDir() + "imu_driver_load_config_zero.yaml";
  std::ofstream(zero) << "camera_imu:\n  rotation_xyzw: [0, 0, 0, 0]\n";
  ros::NodeHandle a("~zero_quaternion");
  a.setParam("camera_imu_file", zero);
  EXPECT_NE(RefusalOf(a).find(zero + ":2: camera_imu.rotation_xyzw: must be a unit quaternion"), std::string::npos)
      << RefusalOf(a);
  const std::string bytes = ::testing::TempDir() + "imu_driver_load_config_bytes.yaml";
  std::ofstream(bytes, std::ios::binary) << "\xfe\xfe\x01\x02";
  ros::NodeHandle b("~random_bytes");
  b.setParam("gyro_calibration_file", bytes);
  EXPECT_EQ(RefusalOf(b), bytes + ": not a text file (invalid UTF-8); expected YAML");
  const std::string gyro = ::testing::TempDir() + "imu_driver_load_config_gyro.yaml";
  std::ofstream(gyro) << "gyro_bias_rad_s: [0.01, 0.02, 0.03]\n";
  ros::NodeHandle c("~gyro_file");
  c.setParam("gyro_calibration_file", gyro);
  const DriverConfig d = LoadConfig(c);
  EXPECT_TRUE(d.gyro_bias_calibrated);
  EXPECT_DOUBLE_EQ(d.gyro_bias_rad_s(1), 0.02);
}

TEST(LoadConfig, WrongTypesAreRefusedByName) {
  ros::NodeHandle a("~wrong_type");
  a.setParam("rate_hz", "fast");
  EXPECT_EQ(RefusalOf(a), "parameter ~rate_hz must be a number");
  ros::NodeHandle b("~wrong_type_nested");
  b.setParam("time_sync/window_s", true);
  EXPECT_EQ(RefusalOf(b), "parameter ~time_sync/window_s must be a number");
  ros::NodeHandle c("~wrong_type_int");
  c.setParam("baud", 115200.5);
  EXPECT_EQ(RefusalOf(c), "parameter ~baud must be an integer");
  ros::NodeHandle d("~wrong_type_list");
  d.setParam("gyro_bias_rad_s", "zero");
  EXPECT_NE(RefusalOf(d).find("wrong_type_list/gyro_bias_rad_s: must be a list of 3 numbers"), std::string::npos)
      << RefusalOf(d);
  ros::NodeHandle e("~wrong_type_bool");
  e.setParam("calibrate_on_start", 1);
  EXPECT_EQ(RefusalOf(e), "parameter ~calibrate_on_start must be true or false");
}

TEST(LoadConfig, TheTableCoversEveryScalarParameter) {
  ros::NodeHandle nh("~every");
  nh.setParam("port", "/dev/ttyS2");
  nh.setParam("baud", 57600);
  nh.setParam("frame_id", "crista");
  nh.setParam("rate_hz", 50);  // an integer where a double is wanted
  nh.setParam("stamp_at_interval_midpoint", false);
  nh.setParam("retry_initial_s", 0.2);
  nh.setParam("retry_max_s", 4.0);
  nh.setParam("time_source", 1);  // an enum's index
  nh.setParam("time_sync/slack_ppm", 30.0);
  nh.setParam("time_sync/window_s", 2.0);
  nh.setParam("time_sync/max_skew_ppm", 500.0);
  nh.setParam("time_sync/jump_threshold_s", 0.2);
  nh.setParam("subtract_gyro_bias", false);
  nh.setParam("publish_in_camera_frame", false);
  nh.setParam("camera_frame_id", "cam");
  nh.setParam("calibration_duration_s", 7.0);
  nh.setParam("calibrate_on_start", true);
  nh.setParam("calibration_output_file", "/tmp/gyro.yaml");
  nh.setParam("stale_after_s", 0.7);
  nh.setParam("rate_tolerance", 0.2);
  nh.setParam("config_file", "");
  nh.setParam("gyro_calibration_file", "");
  nh.setParam("camera_imu_file", "");
  EXPECT_EQ(DriverParamTable().Names().size(), 23u);
  const DriverConfig c = LoadConfig(nh);
  EXPECT_EQ(c.reader.port, "/dev/ttyS2");
  EXPECT_EQ(c.reader.baud, 57600);
  EXPECT_EQ(c.frame_id, "crista");
  EXPECT_DOUBLE_EQ(c.reader.stream.rate_hz, 50.0);
  EXPECT_FALSE(c.stamp_at_interval_midpoint);
  EXPECT_DOUBLE_EQ(c.reader.retry_initial_s, 0.2);
  EXPECT_DOUBLE_EQ(c.reader.retry_max_s, 4.0);
  EXPECT_EQ(c.reader.stream.time_source, StreamConfig::TimeSource::kPps);
  EXPECT_DOUBLE_EQ(c.reader.stream.time_sync.slack_ppm, 30.0);
  EXPECT_DOUBLE_EQ(c.reader.stream.time_sync.window_s, 2.0);
  EXPECT_DOUBLE_EQ(c.reader.stream.time_sync.max_skew_ppm, 500.0);
  EXPECT_DOUBLE_EQ(c.reader.stream.time_sync.jump_threshold_s, 0.2);
  EXPECT_FALSE(c.subtract_gyro_bias);
  EXPECT_FALSE(c.publish_in_camera_frame);
  EXPECT_EQ(c.camera_frame_id, "cam");
  EXPECT_DOUBLE_EQ(c.calibration_duration_s, 7.0);
  EXPECT_TRUE(c.calibrate_on_start);
  EXPECT_EQ(c.calibration_output_file, "/tmp/gyro.yaml");
  EXPECT_DOUBLE_EQ(c.stale_after_s, 0.7);
  EXPECT_DOUBLE_EQ(c.rate_tolerance, 0.2);
}

TEST(LoadConfig, EveryLaunchFileParameterIsInTheTable) {
  for (const std::string node : {"imu_driver_node", "ImuDriverNodelet"}) {
    const auto params = rig_model::LaunchParams(std::string(IMU_DRIVER_DIR) + "/launch/imu_driver.launch", node);
    EXPECT_EQ(params.size(), 7u) << node;
    for (const auto& p : params) EXPECT_TRUE(DriverParamTable().Has(p.name)) << node << ": " << p.name;
    ros::NodeHandle nh("~launch_" + node);
    rig_model::SetLaunchParams(nh, params);  // the $(find ...) files are ~shipped's (load_config.test)
    EXPECT_EQ(RefusalOf(nh), "") << node;
  }
}

}  // namespace
}  // namespace imu_driver

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_load_config");
  return RUN_ALL_TESTS();
}
