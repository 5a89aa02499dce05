// ekf_replay on bags written from the synthetic rig: the TUM trajectory it
// writes must follow the truth; an IMU-only bag runs orientation-only.
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <random>
#include <sstream>

#include "pose_ekf/node/node_config.h"
#include "pose_ekf/node/replay.h"
#include "pose_ekf/node/truth_residuals.h"
#include "pose_ekf/testing/synthetic_cones.h"
#include "pose_ekf/testing/synthetic_rig.h"
#include "pose_math/rotation.h"
#include "ros_messages.h"
#include "tum_file.h"

namespace pose_ekf_test {
namespace {

constexpr double kBagStartS = 1.0;  // the synthetic rig's t = 0 in the bags: ros::Time cannot be 0 in a bag

// with_cones: the first camera pose (it initialises the filter) and, for every camera event, the default layout's
// cones seen from the truth with 1 px noise (synthetic_cones.h) instead of the poses, and the true camera pose
// (rig_sim/ground_truth, as rig_sim records it).
std::string WriteBag(const std::vector<Event>& events, bool with_camera, const std::string& name,
                     bool with_cones = false) {
  const std::string path = ::testing::TempDir() + name;
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  tf2_msgs::TFMessage tf;
  tf.transforms.resize(1);
  tf.transforms[0].header.frame_id = "camera_optical";
  tf.transforms[0].child_frame_id = "imu";
  tf.transforms[0].transform.rotation.w = kQCameraImu.w();
  tf.transforms[0].transform.rotation.x = kQCameraImu.x();
  tf.transforms[0].transform.rotation.y = kQCameraImu.y();
  tf.transforms[0].transform.rotation.z = kQCameraImu.z();
  bag.write("/tf_static", ros::Time(kBagStartS), tf);
  std::mt19937 rng(3);
  bool first_pose = true;
  for (const Event& e : events) {
    ros::Time t;
    t.fromSec(e.stamp_s + kBagStartS);
    if (e.is_camera && with_cones) {
      pose_ekf::ConeFrame f = ObserveCones(e.stamp_s + kBagStartS, e.truth.T_cones_camera, DefaultCones(), {0, 1, 2},
                                           DefaultIntrinsics(), 1.0, &rng);
      bag.write("/cone_tracker/observations", t, ObservationsMsg(f));
      geometry_msgs::PoseStamped truth;
      truth.header.stamp = t;
      truth.header.frame_id = "cones";
      const pose_math::Pose& T = e.truth.T_cones_camera;
      truth.pose.position.x = T.t.x(), truth.pose.position.y = T.t.y(), truth.pose.position.z = T.t.z();
      truth.pose.orientation.w = T.q[0], truth.pose.orientation.x = T.q[1];
      truth.pose.orientation.y = T.q[2], truth.pose.orientation.z = T.q[3];
      bag.write("/rig_sim/ground_truth", t, truth);
    }
    if (e.is_camera && with_camera && (first_pose || !with_cones)) {
      first_pose = false;
      auto msg = CameraMsg(e.camera);
      msg.header.stamp = t;
      bag.write("/cone_tracker/pose", t, msg);
    } else if (!e.is_camera) {
      auto msg = ImuMsg(e.imu);
      msg.header.stamp = t;
      bag.write("/imu/data_raw", t, msg);
    }
  }
  bag.close();
  return path;
}

// Five seconds of the synthetic rig.
std::vector<Event> FiveSeconds() {
  RigSimConfig sim;
  sim.duration_s = 5.0;
  return GenerateRig(sim);
}

TEST(Replay, WritesATumTrajectoryThatFollowsTheTruth) {
  const std::vector<Event> events = FiveSeconds();
  pose_ekf::ReplayOptions o;
  o.bag_path = WriteBag(events, true, "pose_ekf_replay.bag");
  o.output_path = ::testing::TempDir() + "pose_ekf_replay.txt";
  o.covariance_path = ::testing::TempDir() + "pose_ekf_replay_covariance.txt";
  std::ostringstream log;
  const pose_ekf::ReplaySummary s = pose_ekf::RunReplay(o, log);
  EXPECT_FALSE(s.orientation_only);
  EXPECT_EQ(s.imu_rotation_source, "/tf_static camera_optical <- imu") << log.str();
  const auto tum = ReadTum(o.output_path, kBagStartS);
  EXPECT_EQ(tum.size(), s.poses_written);
  EXPECT_GT(tum.size(), 490u);
  double sum_rot2 = 0.0, sum_pos2 = 0.0;
  int n = 0;
  for (const Event& e : events) {
    const auto it = tum.find(std::lround(e.stamp_s * 1000));
    if (e.is_camera || e.stamp_s < 1.0 || it == tum.end()) continue;
    sum_rot2 += std::pow(pose_math::RotationErrorRad(it->second, e.truth.T_cones_camera), 2);
    sum_pos2 += std::pow(pose_math::TranslationError(it->second, e.truth.T_cones_camera), 2);
    ++n;
  }
  ASSERT_GT(n, 390);
  EXPECT_LT(std::sqrt(sum_rot2 / n) * 180 / M_PI, 0.3);
  EXPECT_LT(std::sqrt(sum_pos2 / n), 0.01);

  // --covariance: a line per pose (no bias states by default: stamp and the six variances), and the position's
  // 3 sigma holds the true error at nearly every stamp.
  std::ifstream cov(o.covariance_path);
  std::string line;
  ASSERT_TRUE(std::getline(cov, line));
  EXPECT_EQ(line, "# stamp_s var_x var_y var_z var_rx var_ry var_rz");
  size_t rows = 0;
  int checked = 0, inside = 0;
  std::map<long, const Event*> truth;
  for (const Event& e : events) truth[std::lround(e.stamp_s * 1000)] = &e;
  while (std::getline(cov, line)) {
    std::istringstream fields(line);
    double t, var[6], extra;
    for (double* v : {&t, var, var + 1, var + 2, var + 3, var + 4, var + 5}) ASSERT_TRUE(fields >> *v) << line;
    EXPECT_FALSE(fields >> extra) << line;
    for (double v : var) EXPECT_GT(v, 0.0) << line;
    ++rows;
    const auto it = truth.find(std::lround(t * 1000));
    const auto est = tum.find(std::lround(t * 1000));
    if (t < 1.0 || it == truth.end() || est == tum.end() || it->second->is_camera) continue;
    const Eigen::Vector3d e = est->second.t - it->second->truth.T_cones_camera.t;
    ++checked;
    inside += std::abs(e.x()) <= 3 * std::sqrt(var[0]) && std::abs(e.y()) <= 3 * std::sqrt(var[1]) &&
              std::abs(e.z()) <= 3 * std::sqrt(var[2]);
  }
  EXPECT_EQ(rows, s.poses_written);
  ASSERT_GT(checked, 390);
  EXPECT_GT(inside, 0.95 * checked) << inside << " of " << checked;
}

// A replay of `events` written as cone observations (WriteBag's with_cones), with the per-cone updates on and the
// default layout: the bag and the trajectory are named after `name` in the test's temporary directory.
pose_ekf::ReplayOptions ConeReplay(const std::vector<Event>& events, const std::string& name) {
  pose_ekf::ReplayOptions o;
  o.bag_path = WriteBag(events, true, name + ".bag", true);
  o.output_path = ::testing::TempDir() + name + ".txt";
  o.config.camera_update = static_cast<int>(pose_ekf::CameraUpdate::kCones);
  o.config.layout_file = std::string(POSE_EKF_SOURCE_DIR) + "/../rig_model/config/layouts/default.yaml";
  pose_ekf::LoadLayout(&o.config);
  pose_ekf::ValidateConfig(&o.config);  // as the loaders do: sets ekf.camera_update
  return o;
}

// --cone-log: a line per observation message, its last column the joint NIS of the cones fused. With the pixel noise
// the observations claim, that NIS per degree of freedom (4 a cone: peak and base) averages 1.
TEST(Replay, ConeLogGivesTheFusedConesNis) {
  pose_ekf::ReplayOptions o = ConeReplay(FiveSeconds(), "pose_ekf_replay_cones");
  o.cone_log_path = ::testing::TempDir() + "pose_ekf_replay_cones.log";
  std::ostringstream log;
  const pose_ekf::ReplaySummary s = pose_ekf::RunReplay(o, log);
  EXPECT_GT(s.observation_messages, 140u) << log.str();
  std::ifstream f(o.cone_log_path);
  std::string line;
  ASSERT_TRUE(std::getline(f, line));
  EXPECT_EQ(line,
            "# stamp_s cones ids result fused gated joint_dropped ambiguous too_few own_chi2 rival_chi2 rival_id "
            "sigma_p_m nis own_missed rival_missed own_unexplained rival_unexplained");
  size_t rows = 0;
  double nis_sum = 0.0;
  int dof = 0;
  while (std::getline(f, line)) {
    std::istringstream fields(line);
    std::vector<std::string> c{std::istream_iterator<std::string>(fields), std::istream_iterator<std::string>()};
    ASSERT_EQ(c.size(), 18u) << line;
    ++rows;
    const int fused = std::stoi(c[4]);
    if (std::stod(c[0]) < 2.0 || fused == 0) continue;  // after the first second (stamps start at 1 s)
    nis_sum += std::stod(c[13]);
    dof += 4 * fused;
  }
  EXPECT_EQ(rows, s.observation_messages);
  ASSERT_GT(dof, 4 * 3 * 100);
  EXPECT_NEAR(nis_sum / dof, 1.0, 0.25) << nis_sum << " over " << dof << " degrees of freedom";
}

// --truth-residuals: the observations' pixels against the filter's model at the true pose are the noise the bag
// was written with, 1 px per coordinate and no bias; a bag without the truth gives none.
TEST(Replay, TruthResidualsAreTheObservationsNoise) {
  pose_ekf::ReplayOptions o = ConeReplay(FiveSeconds(), "pose_ekf_replay_truth");
  o.truth_residuals_path = ::testing::TempDir() + "pose_ekf_replay_truth_residuals.txt";
  std::ostringstream log;
  pose_ekf::RunReplay(o, log);
  std::ifstream f(o.truth_residuals_path);
  std::string line;
  ASSERT_TRUE(std::getline(f, line));
  EXPECT_EQ(line, "# stamp_s cone_id depth_m peak_du peak_dv base_du base_dv");
  double sum[4] = {}, sum2[4] = {};
  int n = 0;
  while (std::getline(f, line)) {
    std::istringstream fields(line);
    double t, id, depth, r[4];
    ASSERT_TRUE(fields >> t >> id >> depth >> r[0] >> r[1] >> r[2] >> r[3]) << line;
    EXPECT_GT(depth, 1.0) << line;  // the synthetic rig stays 2-3 m from the cones
    for (int k = 0; k < 4; ++k) sum[k] += r[k], sum2[k] += r[k] * r[k];
    ++n;
  }
  ASSERT_GT(n, 400);  // ~150 frames of three cones
  for (int k = 0; k < 4; ++k) {
    const double mean = sum[k] / n, sd = std::sqrt(sum2[k] / n - mean * mean);
    EXPECT_LT(std::abs(mean), 3.0 / std::sqrt(n)) << k;  // 3 sigma of the mean of unit noise
    EXPECT_NEAR(sd, 1.0, 0.1) << k;
  }
  const std::string summary = "residuals against the truth of " + std::to_string(n) + " cones in ";
  EXPECT_NE(log.str().find(summary), std::string::npos) << log.str();
  EXPECT_NE(log.str().find("(0 frames without truth)"), std::string::npos) << log.str();

  o.bag_path = WriteBag(FiveSeconds(), true, "pose_ekf_replay_no_truth.bag", false);
  std::ostringstream no_truth;
  pose_ekf::RunReplay(o, no_truth);
  EXPECT_NE(no_truth.str().find("residuals against the truth of 0 cones in 0 frames (0 frames without truth)"),
            std::string::npos)
      << no_truth.str();
}

// Position RMS of a TUM trajectory against the events' truth, after the first second.
double PositionRms(const std::map<long, pose_math::Pose>& tum, const std::vector<Event>& events) {
  double sum2 = 0.0;
  int n = 0;
  for (const Event& e : events) {
    const auto it = tum.find(std::lround(e.stamp_s * 1000));
    if (e.is_camera || e.stamp_s < 1.0 || it == tum.end()) continue;
    sum2 += std::pow(pose_math::TranslationError(it->second, e.truth.T_cones_camera), 2);
    ++n;
  }
  return n > 0 ? std::sqrt(sum2 / n) : std::numeric_limits<double>::infinity();
}

// --truth-points: the observations' points replaced by their pixels at the true pose. The filter then follows the
// truth more closely than with the recorded 1 px noise; a value other than peak, base or both is refused.
TEST(Replay, TruthPointsReplaceTheRecordedPixels) {
  const std::vector<Event> events = FiveSeconds();
  pose_ekf::ReplayOptions o = ConeReplay(events, "pose_ekf_replay_truth_points");
  std::ostringstream log;
  pose_ekf::RunReplay(o, log);
  const double recorded = PositionRms(ReadTum(o.output_path, kBagStartS), events);
  o.truth_points = "both";
  pose_ekf::RunReplay(o, log);
  const double exact = PositionRms(ReadTum(o.output_path, kBagStartS), events);
  EXPECT_LT(exact, 0.5 * recorded) << "recorded " << recorded << " m, exact " << exact << " m";
  o.truth_points = "tip";
  try {
    pose_ekf::RunReplay(o, log);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "truth_points is 'tip': must be peak, base or both");
  }
}

// A bias in the tracker's peak is the residual's mean; a stamp between two truth samples takes the pose between them.
TEST(TruthResiduals, APeakBiasIsTheMeanResidual) {
  pose_ekf::TruthResiduals r;
  const pose_math::Pose T = ConeRigStart();
  const Eigen::Quaterniond q = pose_math::EigenFromThesis(T.q);
  r.AddTruth(0.0, T.t - Eigen::Vector3d(0.01, 0.0, 0.0), q);
  r.AddTruth(0.01, T.t + Eigen::Vector3d(0.01, 0.0, 0.0), q);
  std::mt19937 rng(1);
  pose_ekf::ConeFrame f = ObserveCones(0.005, T, DefaultCones(), {0, 1, 2}, DefaultIntrinsics(), 1e-9, &rng);
  ASSERT_EQ(f.cones.size(), 3u);
  for (pose_ekf::ConeObservation& c : f.cones) c.px[0].y() += 2.0;  // 2 px down
  std::ostringstream lines;
  EXPECT_TRUE(r.AddFrame(f, &lines));
  f.stamp_s = 0.5;  // no truth within 10 ms
  EXPECT_FALSE(r.AddFrame(f, &lines));
  const std::string summary = r.Summary();
  EXPECT_EQ(summary.find("residuals against the truth of 3 cones in 1 frames (1 frames without truth): "), 0u)
      << summary;
  EXPECT_NE(summary.find("peak v +2.000 sd 0.000"), std::string::npos) << summary;
  EXPECT_EQ(lines.str().find("0.005000 0 "), 0u) << lines.str();
  std::istringstream first(lines.str());
  double t, id, depth, du, dv, bu, bv;
  ASSERT_TRUE(first >> t >> id >> depth >> du >> dv >> bu >> bv);
  EXPECT_NEAR(dv, 2.0, 1e-6);
  EXPECT_NEAR(du, 0.0, 1e-6);
  EXPECT_NEAR(bu, 0.0, 1e-6);
  EXPECT_NEAR(bv, 0.0, 1e-6);
}

TEST(Replay, ImuOnlyBagRunsOrientationOnly) {
  RigSimConfig sim;
  sim.duration_s = 5.0;
  sim.motion_scale = 0.2;  // gentle motion: gravity dominates the accelerometer
  const std::vector<Event> events = GenerateRig(sim);
  pose_ekf::ReplayOptions o;
  o.bag_path = WriteBag(events, false, "pose_ekf_imu_only.bag");
  o.output_path = ::testing::TempDir() + "pose_ekf_imu_only.txt";
  std::ostringstream log;
  const pose_ekf::ReplaySummary s = pose_ekf::RunReplay(o, log);
  EXPECT_TRUE(s.orientation_only);
  const auto tum = ReadTum(o.output_path, kBagStartS);
  ASSERT_GT(tum.size(), 490u) << log.str();
  // Orientation-only: the IMU frame is the body, heading is arbitrary; the tilt must match.
  // Truth "up" in the IMU frame: R_imu_camera R_cones_cameraᵀ e_z.
  double max_tilt = 0.0;
  for (const Event& e : events) {
    const auto it = tum.find(std::lround(e.stamp_s * 1000));
    if (e.is_camera || e.stamp_s < 1.0 || it == tum.end()) continue;
    const Eigen::Vector3d up_true =
        kQCameraImu.conjugate() *
        (pose_math::RotationFromQuat(e.truth.T_cones_camera.q).transpose() * Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d up_est = pose_math::RotationFromQuat(it->second.q).transpose() * Eigen::Vector3d::UnitZ();
    max_tilt = std::max(max_tilt, std::acos(std::min(1.0, up_true.dot(up_est))));
  }
  EXPECT_LT(max_tilt * 180 / M_PI, 2.0);
}

TEST(Replay, MissingBagIsAClearError) {
  pose_ekf::ReplayOptions o;
  o.bag_path = "/nonexistent/in.bag";
  o.output_path = ::testing::TempDir() + "unused.txt";
  std::ostringstream log;
  try {
    pose_ekf::RunReplay(o, log);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/in.bag"), std::string::npos);
  }
}

TEST(Replay, ShippedConfigFileLoads) {
  const pose_ekf::NodeConfig c = pose_ekf::LoadConfigFile(std::string(POSE_EKF_SOURCE_DIR) + "/config/pose_ekf.yaml");
  EXPECT_EQ(c.cones_frame, "cones");
  EXPECT_EQ(c.ekf.accel_mode, pose_ekf::AccelMode::kPositionAndOrientation);
  EXPECT_DOUBLE_EQ(c.ekf.max_delay_s, 0.2);
}

TEST(Replay, EveryShippedConfigFileLoads) {
  // pose_ekf's own and the rig_sim tuning that sim.launch and replay.launch load.
  for (const std::string& path : {std::string(POSE_EKF_SOURCE_DIR) + "/config/pose_ekf.yaml",
                                  std::string(POSE_EKF_SOURCE_DIR) + "/../ar_bringup/config/pose_ekf_rig_sim.yaml"}) {
    EXPECT_NO_THROW(pose_ekf::LoadConfigFile(path)) << path;
  }
  const pose_ekf::NodeConfig c =
      pose_ekf::LoadConfigFile(std::string(POSE_EKF_SOURCE_DIR) + "/../ar_bringup/config/pose_ekf_rig_sim.yaml");
  EXPECT_TRUE(c.ekf.estimate_gyro_bias);
}

TEST(Replay, MisspeltConfigKeyIsRefusedWithFileLineAndNearestKey) {
  const std::string path = ::testing::TempDir() + "pose_ekf_misspelt.yaml";
  std::ofstream(path) << "# tuning\nuse_camera: true\nsigma_gyr_rad_s: 0.01\n";
  try {
    pose_ekf::LoadConfigFile(path);
    FAIL() << "a misspelt key was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), path + ":3: unknown key 'sigma_gyr_rad_s' (did you mean 'sigma_gyro_rad_s'?)");
  }
  std::ofstream(path) << "\xfe\xff\x01garbage";
  try {
    pose_ekf::LoadConfigFile(path);
    FAIL() << "random bytes were accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": not a text file"), std::string::npos) << e.what();
  }
}

TEST(Replay, KnownParameterNamesAreTheLoaders) {
  const std::vector<std::string> names = pose_ekf::ParamNames();
  for (const char* n : {"cones_frame", "sigma_gyro_rad_s", "use_accel", "accel_mode", "max_predict_step_s"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  }
}

TEST(Replay, BadConfigFileValuesAreNamed) {
  const std::string path = ::testing::TempDir() + "pose_ekf_bad.yaml";
  auto expect_refused = [&](const std::string& yaml, const std::string& name) {
    std::ofstream(path) << yaml;
    try {
      pose_ekf::LoadConfigFile(path);
      ADD_FAILURE() << "accepted " << yaml;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  expect_refused("max_delay_s: -1\n", "max_delay_s");
  expect_refused("accel_mode: sideways\n", "accel_mode");
  expect_refused("sigma_gyro_rad_s: fast\n", "sigma_gyro_rad_s");
  expect_refused("cones_frame: ''\n", "cones_frame");
  expect_refused("camera_gate_chi2: -1\n", "camera_gate_chi2");
  expect_refused("camera_gate_chi2: .inf\n", "camera_gate_chi2");
  expect_refused("reinit_after_rejections: 2.5\n", "reinit_after_rejections");
  expect_refused("reinit_after_rejections: -3\n", "reinit_after_rejections");
}

}  // namespace
}  // namespace pose_ekf_test
