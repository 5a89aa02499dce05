// pose_ekf's parameter table without a master: every parameter the loader read before the table
// (names and the fields they fill), the enums, refusals naming the parameter, file and line, and
// dynamic_reconfigure's PoseEkf.cfg through the same table.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "pose_ekf/PoseEkfConfig.h"
#include "pose_ekf/node/node_config.h"
#include "rig_model/ros/param_table_ros.h"

namespace pose_ekf_test {
namespace {

using pose_ekf::AccelMode;
using pose_ekf::NodeConfig;

std::string Write(const std::string& name, const std::string& yaml) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << yaml;
  return path;
}

std::string RefusalOf(const std::string& path) {
  try {
    pose_ekf::LoadConfigFile(path);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// Every name the loader read before the table (node_config.cpp's Get calls), none left out or added.
TEST(NodeConfig, TheTableHasEveryParameterTheLoaderRead) {
  std::vector<std::string> names = pose_ekf::ParamNames();
  std::vector<std::string> expected = {"cones_frame",
                                       "camera_frame",
                                       "publish_tf",
                                       "output_rate_hz",
                                       "imu_expected_rate_hz",
                                       "camera_expected_rate_hz",
                                       "tf_timeout_s",
                                       "config_file",
                                       "sigma_q_per_sqrt_s",
                                       "sigma_omega_rad_s_per_sqrt_s",
                                       "sigma_p_m_per_sqrt_s",
                                       "sigma_v_m_s_per_sqrt_s",
                                       "sigma_a_m_s2_per_sqrt_s",
                                       "sigma_gyro_bias_rad_s_per_sqrt_s",
                                       "sigma_gyro_rad_s",
                                       "sigma_accel_m_s2",
                                       "use_message_imu_covariance",
                                       "use_camera",
                                       "use_gyro",
                                       "gyro_is_interval_mean",
                                       "gyro_is_centred_interval_mean",
                                       "omega_walk_at_gyro",
                                       "accel_mode",
                                       "quat_integration",
                                       "use_accel",
                                       "gravity_m_s2",
                                       "accel_gate_m_s2",
                                       "camera_gate_chi2",
                                       "reinit_after_rejections",
                                       "estimate_gyro_bias",
                                       "joseph_update",
                                       "init_sigma_omega_rad_s",
                                       "init_sigma_v_m_s",
                                       "init_sigma_a_m_s2",
                                       "init_sigma_gyro_bias_rad_s",
                                       "init_from_gravity",
                                       "init_sigma_tilt_rad",
                                       "init_sigma_heading_rad",
                                       "init_sigma_p_m",
                                       "max_delay_s",
                                       "time_jump_reset_s",
                                       "max_predict_step_s",
                                       "camera_update",
                                       "cone_gate_probability",
                                       "cone_joint_probability",
                                       "reacquire_sigma_p_m",
                                       "reacquire_min_cones",
                                       "cone_ambiguity_margin",
                                       "cone_ambiguity_iterations",
                                       "cone_miss_cost",
                                       "cone_unexplained_cost",
                                       "cone_update_iterations",
                                       "cone_repeat_px",
                                       "cone_repeat_max_s",
                                       "cone_repeat_sigma_v_m_s",
                                       "cone_repeat_sigma_omega_rad_s",
                                       "layout_file",
                                       "model_lever_arm",
                                       "alpha_from_gyro",
                                       "sigma_angular_accel_rad_s2",
                                       "estimate_accel_bias",
                                       "sigma_accel_bias_m_s2_per_sqrt_s",
                                       "init_sigma_accel_bias_m_s2",
                                       "velocity_time_constant_s",
                                       "accel_time_constant_s"};
  std::sort(names.begin(), names.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(names, expected);
}

// A file with every key, none at its default: each lands in its own field.
TEST(NodeConfig, EveryKeyFillsItsField) {
  const std::string path = Write("pose_ekf_every_key.yaml",
                                 "cones_frame: map\ncamera_frame: cam\npublish_tf: false\noutput_rate_hz: 40\n"
                                 "imu_expected_rate_hz: 200\ncamera_expected_rate_hz: 15\ntf_timeout_s: 0.1\n"
                                 "config_file: noted.yaml\n"
                                 "sigma_q_per_sqrt_s: 0.002\nsigma_omega_rad_s_per_sqrt_s: 2.5\n"
                                 "sigma_p_m_per_sqrt_s: 0.003\nsigma_v_m_s_per_sqrt_s: 0.04\n"
                                 "sigma_a_m_s2_per_sqrt_s: 5.5\nsigma_gyro_bias_rad_s_per_sqrt_s: 0.0002\n"
                                 "sigma_gyro_rad_s: 0.02\nsigma_accel_m_s2: 0.3\nuse_message_imu_covariance: true\n"
                                 "use_camera: false\nuse_gyro: false\ngyro_is_interval_mean: true\n"
                                 "accel_mode: orientation\nquat_integration: exact\nuse_accel: true\n"
                                 "gravity_m_s2: 9.81\naccel_gate_m_s2: 0.7\ncamera_gate_chi2: 99.5\n"
                                 "reinit_after_rejections: 9\nestimate_gyro_bias: true\njoseph_update: true\n"
                                 "init_sigma_omega_rad_s: 1.5\ninit_sigma_v_m_s: 0.6\ninit_sigma_a_m_s2: 2.5\n"
                                 "init_sigma_gyro_bias_rad_s: 0.03\ninit_from_gravity: true\n"
                                 "init_sigma_tilt_rad: 0.06\ninit_sigma_heading_rad: 0.2\ninit_sigma_p_m: 1.2\n"
                                 "max_delay_s: 0.3\ntime_jump_reset_s: 0.6\nmax_predict_step_s: 0.01\n"
                                 "model_lever_arm: false\nalpha_from_gyro: false\nsigma_angular_accel_rad_s2: 7.5\n"
                                 "estimate_accel_bias: true\nsigma_accel_bias_m_s2_per_sqrt_s: 0.002\n"
                                 "init_sigma_accel_bias_m_s2: 0.3\nvelocity_time_constant_s: 2.5\n"
                                 "accel_time_constant_s: 0.4\n");
  const NodeConfig c = pose_ekf::LoadConfigFile(path);
  EXPECT_EQ(c.cones_frame, "map");
  EXPECT_EQ(c.camera_frame, "cam");
  EXPECT_FALSE(c.publish_tf);
  EXPECT_EQ(c.output_rate_hz, 40.0);
  EXPECT_EQ(c.imu_expected_rate_hz, 200.0);
  EXPECT_EQ(c.camera_expected_rate_hz, 15.0);
  EXPECT_EQ(c.tf_timeout_s, 0.1);
  EXPECT_EQ(c.config_file, "noted.yaml");
  const pose_ekf::EkfConfig& e = c.ekf;
  EXPECT_EQ(e.sigma_q_per_sqrt_s, 0.002);
  EXPECT_FALSE(e.model_lever_arm);
  EXPECT_FALSE(e.alpha_from_gyro);
  EXPECT_EQ(e.sigma_angular_accel_rad_s2, 7.5);
  EXPECT_TRUE(e.estimate_accel_bias);
  EXPECT_EQ(e.sigma_accel_bias_m_s2_per_sqrt_s, 0.002);
  EXPECT_EQ(e.init_sigma_accel_bias_m_s2, 0.3);
  EXPECT_EQ(e.velocity_time_constant_s, 2.5);
  EXPECT_EQ(e.accel_time_constant_s, 0.4);
  EXPECT_EQ(e.sigma_omega_rad_s_per_sqrt_s, 2.5);
  EXPECT_EQ(e.sigma_p_m_per_sqrt_s, 0.003);
  EXPECT_EQ(e.sigma_v_m_s_per_sqrt_s, 0.04);
  EXPECT_EQ(e.sigma_a_m_s2_per_sqrt_s, 5.5);
  EXPECT_EQ(e.sigma_gyro_bias_rad_s_per_sqrt_s, 0.0002);
  EXPECT_EQ(e.sigma_gyro_rad_s, 0.02);
  EXPECT_EQ(e.sigma_accel_m_s2, 0.3);
  EXPECT_TRUE(e.use_message_imu_covariance);
  EXPECT_FALSE(e.use_camera);
  EXPECT_FALSE(e.use_gyro);
  EXPECT_TRUE(e.gyro_is_interval_mean);
  EXPECT_EQ(e.accel_mode, AccelMode::kOrientation);
  EXPECT_EQ(e.quat_integration, pose_ekf::QuatIntegration::kExact);
  EXPECT_EQ(e.gravity_m_s2, 9.81);
  EXPECT_EQ(e.accel_gate_m_s2, 0.7);
  EXPECT_EQ(e.camera_gate_chi2, 99.5);
  EXPECT_EQ(e.reinit_after_rejections, 9);
  EXPECT_TRUE(e.estimate_gyro_bias);
  EXPECT_TRUE(e.joseph_update);
  EXPECT_EQ(e.init_sigma_omega_rad_s, 1.5);
  EXPECT_EQ(e.init_sigma_v_m_s, 0.6);
  EXPECT_EQ(e.init_sigma_a_m_s2, 2.5);
  EXPECT_EQ(e.init_sigma_gyro_bias_rad_s, 0.03);
  EXPECT_TRUE(e.init_from_gravity);
  EXPECT_EQ(e.init_sigma_tilt_rad, 0.06);
  EXPECT_EQ(e.init_sigma_heading_rad, 0.2);
  EXPECT_EQ(e.init_sigma_p_m, 1.2);
  EXPECT_EQ(e.max_delay_s, 0.3);
  EXPECT_EQ(e.time_jump_reset_s, 0.6);
  EXPECT_EQ(e.max_predict_step_s, 0.01);
}

TEST(NodeConfig, UseAccelSwitchesTheAccelModeOffAndBack) {
  NodeConfig c = pose_ekf::LoadConfigFile(Write("pose_ekf_accel.yaml", "accel_mode: 1\nuse_accel: false\n"));
  EXPECT_EQ(c.ekf.accel_mode, AccelMode::kOff);
  EXPECT_EQ(c.accel_mode, static_cast<int>(AccelMode::kOrientation));  // an enum also takes its index
  c.use_accel = true;
  pose_ekf::ApplyModes(&c);
  EXPECT_EQ(c.ekf.accel_mode, AccelMode::kOrientation);
}

TEST(NodeConfig, WrongTypesAndNamesAreRefusedWithFileAndLine) {
  std::string path = Write("pose_ekf_wrong_type.yaml", "use_camera: true\nsigma_gyro_rad_s: fast\n");
  EXPECT_EQ(RefusalOf(path), path + ":2: sigma_gyro_rad_s: must be a number");
  path = Write("pose_ekf_wrong_enum.yaml", "accel_mode: sideways\n");
  EXPECT_EQ(RefusalOf(path),
            path + ":1: accel_mode: must be one of off, orientation, position_orientation (got 'sideways')");
  path = Write("pose_ekf_wrong_bool.yaml", "\nuse_gyro: maybe\n");
  EXPECT_EQ(RefusalOf(path), path + ":2: use_gyro: must be true or false");
  path = Write("pose_ekf_wrong_int.yaml", "reinit_after_rejections: 2.5\n");
  EXPECT_EQ(RefusalOf(path), path + ":1: reinit_after_rejections: must be an integer");
  path = Write("pose_ekf_misspelt_enum.yaml", "accel_mod: orientation\n");
  EXPECT_EQ(RefusalOf(path), path + ":1: unknown key 'accel_mod' (did you mean 'accel_mode'?)");
  path = Write("pose_ekf_range.yaml", "reinit_after_rejections: 2000000\n");
  EXPECT_NE(RefusalOf(path).find(path + ": reinit_after_rejections must be a whole number in [0, 1000]"),
            std::string::npos)
      << RefusalOf(path);
}

// Every name of PoseEkf.cfg is in the table, and config -> cfg -> config is the identity.
TEST(NodeConfig, ReconfigureRoundTripIsTheIdentity) {
  NodeConfig c;
  c.ekf.sigma_q_per_sqrt_s = 0.002;
  c.ekf.sigma_omega_rad_s_per_sqrt_s = 2.5;
  c.ekf.sigma_p_m_per_sqrt_s = 0.003;
  c.ekf.sigma_v_m_s_per_sqrt_s = 0.04;
  c.ekf.sigma_a_m_s2_per_sqrt_s = 5.5;
  c.ekf.sigma_gyro_bias_rad_s_per_sqrt_s = 0.0002;
  c.ekf.sigma_gyro_rad_s = 0.02;
  c.ekf.sigma_accel_m_s2 = 0.3;
  c.ekf.accel_gate_m_s2 = 0.7;
  c.ekf.camera_gate_chi2 = 99.5;
  c.ekf.reinit_after_rejections = 9;
  c.ekf.use_camera = false;
  c.ekf.use_gyro = false;
  c.use_accel = false;
  c.ekf.joseph_update = true;
  c.camera_update = static_cast<int>(pose_ekf::CameraUpdate::kCones);
  const pose_ekf::PoseEkfConfig cfg =
      rig_model::ToReconfigure<NodeConfig, pose_ekf::PoseEkfConfig>(pose_ekf::Params(), c);
  EXPECT_EQ(cfg.sigma_gyro_rad_s, 0.02);
  EXPECT_EQ(cfg.reinit_after_rejections, 9);
  EXPECT_FALSE(cfg.use_accel);
  EXPECT_TRUE(cfg.joseph_update);

  NodeConfig back;  // defaults: every reconfigurable value must come from cfg
  rig_model::FromReconfigure(pose_ekf::Params(), cfg, &back);
  dynamic_reconfigure::Config msg;
  cfg.__toMessage__(msg);
  std::vector<std::string> names;
  for (const auto& p : msg.doubles) names.push_back(p.name);
  for (const auto& p : msg.ints) names.push_back(p.name);
  for (const auto& p : msg.bools) names.push_back(p.name);
  for (const std::string& name : names) {
    EXPECT_EQ(pose_ekf::Params().Get(back, name), pose_ekf::Params().Get(c, name)) << name;
  }
  EXPECT_EQ(names.size(), 18u);  // PoseEkf.cfg's parameters
  pose_ekf::ApplyModes(&back);
  EXPECT_EQ(back.ekf.accel_mode, AccelMode::kOff);
  EXPECT_EQ(back.ekf.camera_update, pose_ekf::CameraUpdate::kCones);

  NodeConfig same = c;  // onto the config it came from: nothing changes
  rig_model::FromReconfigure(pose_ekf::Params(), cfg, &same);
  for (const std::string& name : pose_ekf::ParamNames()) {
    EXPECT_EQ(pose_ekf::Params().Get(same, name), pose_ekf::Params().Get(c, name)) << name;
  }
}

}  // namespace
}  // namespace pose_ekf_test
