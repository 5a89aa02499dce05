// Camera poses as messages (no master): non-unit quaternions are normalised
// and counted, zero or non-finite fields are refused naming the topic and the
// field, and the ten wrong poses do not move a tracking filter.
#include <unistd.h>

#include <gtest/gtest.h>

#include <fstream>
#include <limits>

#include "pose_ekf/node/pose_ekf_adapter.h"
#include "pose_ekf/testing/synthetic_rig.h"
#include "pose_math/rotation.h"
#include "ros_messages.h"

namespace pose_ekf_test {
namespace {

using pose_ekf::AddResult;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void Scale(geometry_msgs::Quaternion& q, double s) {
  q.w *= s;
  q.x *= s;
  q.y *= s;
  q.z *= s;
}

TEST(AdapterCameraInput, NonUnitQuaternionIsNormalisedAndCountedWhenFar) {
  RigSimConfig sim;
  sim.duration_s = 0.0;
  const pose_ekf::CameraMeasurement m = GenerateRig(sim).front().camera;
  std::string why;
  pose_ekf::PoseEkfAdapter adapter{pose_ekf::NodeConfig{}};
  geometry_msgs::PoseWithCovarianceStamped msg = CameraMsg(m);
  Scale(msg.pose.pose.orientation, 2.0);
  ASSERT_EQ(adapter.HandleCamera(msg, &why), AddResult::kInitialized) << why;
  EXPECT_EQ(adapter.camera_quaternions_normalized(), 1u);
  EXPECT_LT((adapter.buffer().filter().Pose().pose.q - m.T_cones_camera.q).norm(), 1e-12);
  // The covariance is the same as from the unit quaternion.
  EXPECT_LT((adapter.buffer().filter().Pose().cov - m.cov).norm(), 1e-12 * m.cov.norm());

  // Within | |q|² - 1 | <= 0.01 (float rounding, a few steps of integration): used, not counted.
  pose_ekf::PoseEkfAdapter near{pose_ekf::NodeConfig{}};
  msg = CameraMsg(m);
  Scale(msg.pose.pose.orientation, std::sqrt(1.009));
  ASSERT_EQ(near.HandleCamera(msg, &why), AddResult::kInitialized) << why;
  EXPECT_EQ(near.camera_quaternions_normalized(), 0u);
  EXPECT_FALSE(pose_ekf::QuaternionFarFromUnit(msg.pose.pose.orientation));
  Scale(msg.pose.pose.orientation, std::sqrt(0.98 / 1.009));
  EXPECT_TRUE(pose_ekf::QuaternionFarFromUnit(msg.pose.pose.orientation));
}

TEST(AdapterCameraInput, ZeroOrNonFiniteFieldsAreRefusedNamingTopicAndField) {
  RigSimConfig sim;
  sim.duration_s = 0.0;
  const geometry_msgs::PoseWithCovarianceStamped good = CameraMsg(GenerateRig(sim).front().camera);
  pose_ekf::PoseEkfAdapter adapter{pose_ekf::NodeConfig{}};
  auto expect_refused = [&](geometry_msgs::PoseWithCovarianceStamped msg, AddResult result, const std::string& field) {
    std::string why;
    EXPECT_EQ(adapter.HandleCamera(msg, &why), result) << why;
    EXPECT_NE(why.find("cone_tracker/pose"), std::string::npos) << why;
    EXPECT_NE(why.find(field), std::string::npos) << why;
  };
  geometry_msgs::PoseWithCovarianceStamped msg = good;
  Scale(msg.pose.pose.orientation, 0.0);
  expect_refused(msg, AddResult::kRejectedInvalid, "pose.pose.orientation");
  msg = good;
  msg.pose.pose.orientation.y = kNaN;
  expect_refused(msg, AddResult::kRejectedNonFinite, "pose.pose.orientation");
  msg = good;
  msg.pose.pose.orientation.w = std::numeric_limits<double>::infinity();
  expect_refused(msg, AddResult::kRejectedNonFinite, "pose.pose.orientation");
  msg = good;
  msg.pose.pose.position.z = kNaN;
  expect_refused(msg, AddResult::kRejectedNonFinite, "pose.pose.position");
  msg = good;
  msg.pose.covariance[7] = -std::numeric_limits<double>::infinity();
  expect_refused(msg, AddResult::kRejectedNonFinite, "pose.covariance");
  msg = good;
  msg.pose.covariance[35] = 0.0;
  expect_refused(msg, AddResult::kRejectedInvalid, "pose.covariance");
  EXPECT_EQ(adapter.camera_rejected(), 6u);
  EXPECT_EQ(adapter.nan_rejected(), 4u);
  EXPECT_EQ(adapter.invalid_rejected(), 2u);
  EXPECT_FALSE(adapter.buffer().filter().initialized());
  std::string why;
  EXPECT_EQ(adapter.HandleCamera(good, &why), AddResult::kInitialized) << why;
}

// The issue: ten wrong poses, finite or with a non-unit quaternion, drove the
// filter to x = -80 m in 6 s. Now none is fused and each is counted and explained.
TEST(AdapterCameraInput, TenWrongPosesDoNotMoveATrackingFilter) {
  RigSimConfig sim;
  sim.duration_s = 6.0;
  pose_ekf::PoseEkfAdapter adapter{pose_ekf::NodeConfig{}};
  int wrong = 0;
  double max_error_m = 0.0;
  std::string why;
  for (const Event& e : GenerateRig(sim)) {
    if (!e.is_camera) {
      adapter.HandleImu(ImuMsg(e.imu), kQCameraImu, &why);
      if (e.stamp_s > 1.0) {
        max_error_m =
            std::max(max_error_m, (adapter.buffer().filter().Pose().pose.t - e.truth.T_cones_camera.t).norm());
      }
      continue;
    }
    geometry_msgs::PoseWithCovarianceStamped msg = CameraMsg(e.camera);
    if (e.stamp_s > 2.0 && wrong < 10) {
      msg.pose.pose.position.x -= 80.0 * (wrong + 1) / 10.0;  // up to -80 m
      if (wrong % 2) {
        msg.pose.pose.orientation.x += 0.7;  // also a 0.7 non-unit component
      }
      ++wrong;
      ASSERT_EQ(adapter.HandleCamera(msg, &why), AddResult::kGated);
      EXPECT_NE(why.find("chi-square gate"), std::string::npos) << why;
      continue;
    }
    adapter.HandleCamera(msg, &why);
  }
  EXPECT_EQ(wrong, 10);
  EXPECT_EQ(adapter.buffer().counters().camera_gated, 10u);
  EXPECT_EQ(adapter.buffer().counters().reinits, 0u);
  EXPECT_EQ(adapter.camera_quaternions_normalized(), 5u);
  EXPECT_LT(max_error_m, 0.02);
}

TEST(AdapterCameraInput, GateParametersAreLoaded) {
  const std::string path = ::testing::TempDir() + "pose_ekf_gate_params_" + std::to_string(getpid()) + ".yaml";
  std::ofstream(path) << "camera_gate_chi2: 50.5\nreinit_after_rejections: 7\n";
  const pose_ekf::NodeConfig c = pose_ekf::LoadConfigFile(path);
  EXPECT_DOUBLE_EQ(c.ekf.camera_gate_chi2, 50.5);
  EXPECT_EQ(c.ekf.reinit_after_rejections, 7);
  // Bad values are refused naming them: Replay.BadConfigFileValuesAreNamed.
}

}  // namespace
}  // namespace pose_ekf_test
