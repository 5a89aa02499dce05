// ekf_replay on IMU bags from other robots (../shared/data/rosbags_third_party, robot_localization's test bags:
// other topic names, 30-183 Hz, orientation-only with config/imu_only.yaml). No truth comes with them; each IMU
// message carries its robot's own orientation estimate, and the tilt (the gravity direction in the IMU frame) of
// ours is compared with it.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Imu.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "pose_ekf/node/node_config.h"
#include "pose_ekf/node/replay.h"
#include "pose_math/rotation.h"
#include "rig_model/shared_data.h"
#include "tum_file.h"

namespace pose_ekf_test {
namespace {

struct ThirdPartyBag {
  const char* name;
  const char* imu_topic;
  double max_median_tilt_deg;  // against the robot's own estimate, which is no truth
};

// "Up" in the body frame for an orientation body -> world.
Eigen::Vector3d UpInBody(const pose_math::Quat& q) {
  return pose_math::RotationFromQuat(q).transpose() * Eigen::Vector3d::UnitZ();
}

class ThirdParty : public ::testing::TestWithParam<ThirdPartyBag> {};

TEST_P(ThirdParty, ImuOnlyTiltFollowsTheRobotsOwnEstimate) {
  const ThirdPartyBag& b = GetParam();
  const std::string dir =
      rig_model::SharedDataDir(POSE_EKF_SOURCE_DIR, "rosbags_third_party", "test2.bag", "POSE_EKF_THIRD_PARTY_BAGS");
  if (dir.empty()) GTEST_SKIP() << "../shared/data/rosbags_third_party not found: third-party bag test skipped";
  pose_ekf::ReplayOptions o;
  o.bag_path = dir + "/" + b.name;
  o.imu_topic = b.imu_topic;
  o.output_path = ::testing::TempDir() + "pose_ekf_third_party_" + b.name + ".txt";
  o.config = pose_ekf::LoadConfigFile(std::string(POSE_EKF_SOURCE_DIR) + "/config/imu_only.yaml");
  std::ostringstream log;
  const pose_ekf::ReplaySummary s = pose_ekf::RunReplay(o, log);
  EXPECT_TRUE(s.orientation_only);
  EXPECT_EQ(s.poses_written, s.imu_messages) << log.str();

  const std::map<long, pose_math::Pose> ours = ReadTum(o.output_path, 0.0);  // by stamp in milliseconds
  rosbag::Bag bag(o.bag_path);
  std::vector<double> tilt_deg;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(b.imu_topic))) {
    const sensor_msgs::Imu::ConstPtr imu = m.instantiate<sensor_msgs::Imu>();
    const auto it = imu ? ours.find(std::lround(imu->header.stamp.toSec() * 1000)) : ours.end();
    if (it == ours.end()) continue;
    const auto& q = imu->orientation;
    const Eigen::Vector3d up_theirs = UpInBody(pose_math::Quat(q.w, q.x, q.y, q.z).normalized());
    tilt_deg.push_back(std::acos(std::min(1.0, up_theirs.dot(UpInBody(it->second.q)))) * 180.0 / M_PI);
  }
  ASSERT_GT(tilt_deg.size(), s.imu_messages * 9 / 10);
  std::sort(tilt_deg.begin(), tilt_deg.end());
  const double median = tilt_deg[tilt_deg.size() / 2], p95 = tilt_deg[tilt_deg.size() * 95 / 100];
  std::printf(
      "[ third party ] %s (%s, %zu IMU messages): tilt against the robot's own estimate median %.2f deg, "
      "p95 %.2f deg\n",
      b.name, b.imu_topic, s.imu_messages, median, p95);
  EXPECT_LT(median, b.max_median_tilt_deg);
}

// A bag whose IMU topic is not the one given: no trajectory, and a message that names the bag's IMU topics.
TEST(ThirdPartyTopics, AnotherImuTopicIsNamed) {
  const std::string path = ::testing::TempDir() + "pose_ekf_other_imu_topic.bag";
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    sensor_msgs::Imu imu;
    imu.header.stamp = ros::Time(1.0);
    imu.linear_acceleration.z = 9.81;
    bag.write("/robot/imu", imu.header.stamp, imu);
  }
  pose_ekf::ReplayOptions o;
  o.bag_path = path;
  o.output_path = ::testing::TempDir() + "pose_ekf_other_imu_topic.txt";
  std::ostringstream log;
  try {
    pose_ekf::RunReplay(o, log);
    FAIL() << "replayed a bag without samples on " << o.imu_topic;
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), path +
                                         ": no sensor_msgs/Imu on 'imu/data_raw' and no camera poses on "
                                         "'cone_tracker/pose'; the bag's sensor_msgs/Imu topics: /robot/imu "
                                         "(--imu-topic), its geometry_msgs/PoseWithCovarianceStamped topics: none "
                                         "(--camera-topic)");
  }
}

// Husky and Jackal (IMU with its own filter, 30 and 50 Hz); the AR.Drone's own estimate (183 Hz) is the rougher.
INSTANTIATE_TEST_SUITE_P(Bags, ThirdParty,
                         ::testing::Values(ThirdPartyBag{"test1.bag", "/imu/data", 1.5},
                                           ThirdPartyBag{"test2.bag", "/imu/data", 1.5},
                                           ThirdPartyBag{"test3_groovy.bag", "/ardrone/imu", 4.0}),
                         [](const auto& info) { return std::string(info.param.name).substr(0, 5); });

}  // namespace
}  // namespace pose_ekf_test
