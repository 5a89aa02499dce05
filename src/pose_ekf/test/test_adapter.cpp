// Replay-style test of the ROS adapter without a master: the synthetic rig's
// measurements become the nodelet's input messages (IMU in its own frame,
// REP-145), are fed through PoseEkfAdapter, and must give the same estimate as
// the core fed directly.
#include <gtest/gtest.h>

#include <limits>

#include "pose_ekf/node/pose_ekf_adapter.h"
#include "pose_ekf/testing/synthetic_rig.h"
#include "pose_math/covariance.h"
#include "pose_math/rotation.h"
#include "ros_messages.h"

namespace pose_ekf_test {
namespace {

using pose_ekf::AddResult;

pose_ekf::NodeConfig Config() { return pose_ekf::NodeConfig{}; }

TEST(Adapter, ReplayMatchesTheCoreAndTracksTruth) {
  RigSimConfig sim;
  sim.duration_s = 5.0;
  const std::vector<Event> events = GenerateRig(sim);
  pose_ekf::PoseEkfAdapter adapter(Config());
  pose_ekf::MeasurementBuffer core(Config().ekf);
  double max_rot_err = 0.0;
  for (const Event& e : events) {
    std::string why;
    if (e.is_camera) {
      const AddResult r = adapter.HandleCamera(CameraMsg(e.camera), &why);
      ASSERT_TRUE(r == AddResult::kApplied || r == AddResult::kInitialized) << ToString(r) << " " << why;
      core.AddCamera(e.camera);
    } else {
      adapter.HandleImu(ImuMsg(e.imu), kQCameraImu, &why);
      core.AddImu(e.imu);
      pose_ekf::AdapterOutputs out;
      if (e.stamp_s > 1.0 && adapter.MakeOutputs(&out)) {
        const auto& o = out.pose.pose.pose.orientation;
        const pose_math::Pose est{pose_math::Quat(o.w, o.x, o.y, o.z),
                                  Eigen::Vector3d(out.tf.transform.translation.x, out.tf.transform.translation.y,
                                                  out.tf.transform.translation.z)};
        max_rot_err = std::max(max_rot_err, pose_math::RotationErrorRad(est, e.truth.T_cones_camera));
      }
    }
  }
  EXPECT_LT((adapter.buffer().filter().state().x - core.filter().state().x).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(max_rot_err, 0.5 * M_PI / 180.0);
  EXPECT_EQ(adapter.buffer().counters().gyro_applied, core.counters().gyro_applied);
}

TEST(Adapter, OutputsCarryFramesStampAndTwistInTheCameraFrame) {
  RigSimConfig sim;
  sim.duration_s = 2.0;
  pose_ekf::PoseEkfAdapter adapter(Config());
  std::string why;
  pose_ekf::AdapterOutputs out;
  EXPECT_FALSE(adapter.MakeOutputs(&out));  // nothing before the first camera pose
  for (const Event& e : GenerateRig(sim)) {
    e.is_camera ? adapter.HandleCamera(CameraMsg(e.camera), &why) : adapter.HandleImu(ImuMsg(e.imu), kQCameraImu, &why);
  }
  ASSERT_TRUE(adapter.MakeOutputs(&out));
  EXPECT_EQ(out.tf.header.frame_id, "cones");
  EXPECT_EQ(out.tf.child_frame_id, "camera_optical");
  EXPECT_EQ(out.odometry.child_frame_id, "camera_optical");
  EXPECT_DOUBLE_EQ(out.pose.header.stamp.toSec(), 2.0);
  const auto& f = adapter.buffer().filter();
  const Eigen::Vector3d v_camera = pose_math::RotationFromQuat(f.Pose().pose.q).transpose() * f.v_cones_m_s();
  EXPECT_NEAR(out.odometry.twist.twist.linear.x, v_camera.x(), 1e-12);
  EXPECT_NEAR(out.odometry.twist.twist.angular.z, f.omega_camera_rad_s().z(), 1e-12);
  const Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>> cov(out.pose.pose.covariance.data());
  EXPECT_LT((cov - cov.transpose()).norm(), 1e-15);
  EXPECT_GT(cov.diagonal().minCoeff(), 0.0);
  // The fixed-rate output predicts forward without touching the filter.
  pose_ekf::AdapterOutputs ahead;
  ASSERT_TRUE(adapter.MakePredictedOutputs(2.025, &ahead));
  EXPECT_DOUBLE_EQ(ahead.pose.header.stamp.toSec(), 2.025);
  EXPECT_DOUBLE_EQ(f.state().stamp_s, 2.0);
}

TEST(Adapter, BadMessagesAreRefusedNamedAndCounted) {
  pose_ekf::PoseEkfAdapter adapter(Config());
  RigSimConfig sim;
  sim.duration_s = 0.0;
  const std::vector<Event> events = GenerateRig(sim);
  geometry_msgs::PoseWithCovarianceStamped cam = CameraMsg(events.front().camera);
  std::string why;
  cam.header.frame_id = "map";
  EXPECT_EQ(adapter.HandleCamera(cam, &why), AddResult::kRejectedInvalid);
  EXPECT_NE(why.find("map"), std::string::npos) << why;
  cam.header.frame_id = "cones";
  cam.pose.covariance[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(adapter.HandleCamera(cam, &why), AddResult::kRejectedNonFinite);
  cam.pose.covariance[0] = 0.0;
  EXPECT_EQ(adapter.HandleCamera(cam, &why), AddResult::kRejectedInvalid);
  sensor_msgs::Imu imu = ImuMsg(events.back().imu);
  imu.angular_velocity_covariance[0] = -1.0;
  imu.linear_acceleration_covariance[0] = -1.0;
  EXPECT_EQ(adapter.HandleImu(imu, kQCameraImu, &why), AddResult::kRejectedInvalid);
  imu = ImuMsg(events.back().imu);
  imu.linear_acceleration.y = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(adapter.HandleImu(imu, kQCameraImu, &why), AddResult::kRejectedNonFinite);
  EXPECT_EQ(adapter.invalid_rejected(), 3u);
  EXPECT_EQ(adapter.nan_rejected() + adapter.buffer().counters().nan_rejected, 2u);
  EXPECT_FALSE(adapter.buffer().filter().initialized());
}

TEST(Adapter, Rep145MissingGyroIsNotUsed) {
  pose_ekf::ImuMeasurement m;
  sensor_msgs::Imu msg;
  msg.header.frame_id = "imu";
  msg.angular_velocity_covariance[0] = -1.0;
  msg.linear_acceleration.z = 9.8;
  std::string why;
  ASSERT_EQ(pose_ekf::ImuFromMsg(msg, kQCameraImu, &m, &why), pose_ekf::ConversionResult::kOk);
  EXPECT_FALSE(m.has_gyro);
  EXPECT_TRUE(m.has_accel);
  EXPECT_FALSE(m.has_covariance);
  EXPECT_LT((m.accel_camera_m_s2 - kQCameraImu * Eigen::Vector3d(0, 0, 9.8)).norm(), 1e-12);
}

// The tf's translation is the lever arm: it reaches the measurement, and one longer than 1 m is
// refused with the tf and the calibration field named.
TEST(Adapter, LeverArmFromTheTfAndAbsurdOnesRefused) {
  pose_ekf::ImuMeasurement m;
  sensor_msgs::Imu msg;
  msg.header.frame_id = "imu";
  msg.linear_acceleration.z = 9.8;
  std::string why;
  const Eigen::Vector3d r(0.02, 0.08, -0.06);
  ASSERT_EQ(pose_ekf::ImuFromMsg(msg, kQCameraImu, &m, &why, r), pose_ekf::ConversionResult::kOk);
  EXPECT_EQ(m.p_imu_in_camera_m, r);
  EXPECT_EQ(pose_ekf::CheckLeverArm(r, "camera_optical", "imu"), "");
  EXPECT_EQ(pose_ekf::CheckLeverArm(Eigen::Vector3d(0.0, 0.999, 0.0), "camera_optical", "imu"), "");
  const std::string refused = pose_ekf::CheckLeverArm(Eigen::Vector3d(0.0, 1.2, 0.0), "camera_optical", "imu");
  EXPECT_NE(refused.find("camera_imu.translation_m"), std::string::npos) << refused;
  EXPECT_NE(refused.find("camera_optical -> imu"), std::string::npos) << refused;
  EXPECT_NE(refused.find("1.2 m"), std::string::npos) << refused;
  EXPECT_NE(pose_ekf::CheckLeverArm(Eigen::Vector3d(NAN, 0.0, 0.0), "camera_optical", "imu"), "");
}

}  // namespace
}  // namespace pose_ekf_test
