// The nodelet in a manager (launch/cone_tracker.launch), fed the sample bag in
// lockstep: each frame is published only after the previous frame's
// cone_tracker/detections came back, so no frame is dropped and the run does
// not depend on machine load. Checks the poses against rig_sim/ground_truth.
#include <gtest/gtest.h>

#include <ros/ros.h>
#include <algorithm>

#include <cstdio>
#include <set>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <visualization_msgs/MarkerArray.h>

#include "bag_replay.h"
#include "cone_tracker/ConeDetections.h"
#include "cone_tracker/ConeObservations.h"
#include "cone_tracker/node/layout.h"
#include "handheld_limits.h"
#include "nodelet_test_util.h"

namespace cone_tracker {
namespace {

struct Listener {
  std::map<uint64_t, geometry_msgs::PoseWithCovarianceStamped> poses;
  std::map<uint64_t, ConeDetections> detections;
  std::map<uint64_t, ConeObservations> observations;
  visualization_msgs::MarkerArrayConstPtr markers;
  std::map<std::string, std::string> diagnostics;  // the latest "cone_tracker: tracker" values
  std::vector<ros::Subscriber> subs;
  explicit Listener(ros::NodeHandle& nh) {
    subs.push_back(nh.subscribe<geometry_msgs::PoseWithCovarianceStamped>(
        "cone_tracker/pose", 100, [this](const auto& m) { poses[m->header.stamp.toNSec()] = *m; }));
    subs.push_back(nh.subscribe<ConeDetections>("cone_tracker/detections", 100,
                                                [this](const auto& m) { detections[m->header.stamp.toNSec()] = *m; }));
    subs.push_back(nh.subscribe<ConeObservations>(
        "cone_tracker/observations", 100, [this](const auto& m) { observations[m->header.stamp.toNSec()] = *m; }));
    subs.push_back(
        nh.subscribe<visualization_msgs::MarkerArray>("cone_tracker/cones", 1, [this](const auto& m) { markers = m; }));
    subs.push_back(nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10, [this](const auto& m) {
      for (const auto& s : m->status)
        if (s.name == "cone_tracker: tracker")
          for (const auto& kv : s.values) diagnostics[kv.key] = kv.value;
    }));
  }
};

}  // namespace

TEST(NodeletReplay, HandheldSampleInLockstep) {
  std::vector<ConeModel> layout;
  std::string error;
  ASSERT_TRUE(LoadLayoutFile(RIG_MODEL_LAYOUTS_DIR "/default.yaml", &layout, &error)) << error;
  const std::vector<BagFrame> frames = ReadBag(CONE_TRACKER_ROSBAGS_DIR "/handheld_sample.bag", layout, 6.0);
  ASSERT_EQ(frames.size(), 240u);

  ros::NodeHandle nh;
  Listener listener(nh);
  ros::Publisher image_pub = nh.advertise<sensor_msgs::Image>("camera/image_raw", 1);
  ros::Publisher info_pub = nh.advertise<sensor_msgs::CameraInfo>("camera/camera_info", 1, /*latch=*/true);
  // Both ways: the nodelet takes the camera topics, and this test takes its pose, detections and observations (a
  // frame processed before those connect is lost to the test, and the wait below for it would never end).
  ASSERT_TRUE(SpinUntil(
      [&] {
        return image_pub.getNumSubscribers() > 0 && info_pub.getNumSubscribers() > 0 &&
               std::all_of(listener.subs.begin(), listener.subs.begin() + 3,
                           [](const ros::Subscriber& s) { return s.getNumPublishers() > 0; });
      },
      60.0))
      << "the nodelet and this test did not connect (camera/image_raw, camera/camera_info, cone_tracker/pose, "
         "cone_tracker/detections, cone_tracker/observations)";
  info_pub.publish(frames.front().info);
  // camera_info travels on its own connection and may reach the nodelet after the first frame: until
  // it has, the nodelet counts the frame as without camera_info (and publishes no detections), so
  // the first frame is sent again. No wall-clock wait decides it.
  int resent = 0;
  for (;; ++resent) {
    ASSERT_LT(resent, 50) << "the nodelet never received camera_info";
    const uint64_t stamp = frames.front().image->header.stamp.toNSec();
    listener.diagnostics.clear();
    image_pub.publish(frames.front().image);
    ASSERT_TRUE(SpinUntil(
        [&] {
          return listener.detections.count(stamp) > 0 ||
                 (listener.diagnostics["frames"] == std::to_string(resent + 1) &&
                  listener.diagnostics["frames without camera_info"] == std::to_string(resent + 1));
        },
        60.0))
        << "neither detections nor a frame without camera_info in /diagnostics";
    if (listener.detections.count(stamp) > 0) break;
  }

  int lost = 0;
  for (size_t i = 1; i < frames.size(); ++i) {
    const uint64_t stamp = frames[i].image->header.stamp.toNSec();
    image_pub.publish(frames[i].image);
    if (!SpinUntil([&] { return listener.detections.count(stamp) > 0; }, 60.0)) ++lost;
  }
  EXPECT_EQ(lost, 0) << "frames without cone_tracker/detections";
  // A pose may trail its detections (another connection): wait for every pose the detections announce.
  size_t announced = 0;
  for (const auto& [stamp, d] : listener.detections) announced += d.pose_published ? 1 : 0;
  EXPECT_TRUE(SpinUntil([&] { return listener.poses.size() >= announced; }, 60.0))
      << listener.poses.size() << " poses of " << announced << " announced";

  const Accuracy a = Evaluate(frames, listener.poses);
  std::printf("ACCURACY nodelet replay handheld_sample: %s\n", a.Summary().c_str());
  ExpectHandheldSampleAccuracy(a);  // the adapter replay's limits: the nodelet adds wiring only
  for (const auto& [stamp, d] : listener.detections) {
    EXPECT_EQ(d.pose_published, listener.poses.count(stamp) > 0) << d.status;
    for (const auto& c : d.detections) EXPECT_LT(c.cone_id, int(layout.size()));
  }
  for (const auto& [stamp, p] : listener.poses) EXPECT_EQ(p.header.frame_id, "cones");
  // Every frame with a pose also gives cone_tracker/observations with the pose's correspondence.
  EXPECT_TRUE(SpinUntil([&] { return listener.observations.size() >= announced; }, 60.0))
      << listener.observations.size() << " observations, " << announced << " poses";
  for (const auto& [stamp, d] : listener.detections) {
    if (!d.pose_published) continue;
    const auto o = listener.observations.find(stamp);
    ASSERT_NE(o, listener.observations.end()) << "no observations for a frame with a pose";
    std::multiset<int> pose_ids, observed_ids;
    for (const auto& c : d.detections)
      if (c.cone_id >= 0) pose_ids.insert(c.cone_id);
    for (const auto& c : o->second.cones) observed_ids.insert(c.cone_id);
    EXPECT_EQ(pose_ids, observed_ids);
    EXPECT_GT(o->second.fx, 0.0);
  }

  // The nodelet's own account of the run (the latencies are wall-clock figures on a shared machine:
  // printed, not asserted).
  const std::string sent = std::to_string(frames.size() + size_t(resent));
  ASSERT_TRUE(SpinUntil([&] { return listener.diagnostics["frames"] == sent; }, 60.0))
      << "frames in /diagnostics: " << listener.diagnostics["frames"];
  EXPECT_EQ(listener.diagnostics["poses published"], std::to_string(listener.poses.size()));
  EXPECT_GE(std::stoul(listener.diagnostics["observations published"]), listener.observations.size());
  std::printf("OBSERVATIONS nodelet replay: %zu messages for %zu poses; /diagnostics says %s\n",
              listener.observations.size(), announced, listener.diagnostics["observations published"].c_str());
  for (const char* key :
       {"processing time mean (ms)", "processing time max (ms)", "cones found (mean per segmented frame)",
        "rejected by chi-square gate", "frames with too few cones"})
    std::printf("DIAGNOSTICS %s: %s\n", key, listener.diagnostics[key].c_str());

  ASSERT_TRUE(listener.markers) << "no latched cone_tracker/cones";
  int cones = 0;
  for (const auto& m : listener.markers->markers) cones += m.ns == "cone_tracker/layout";
  EXPECT_EQ(cones, 3);
}

}  // namespace cone_tracker

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "cone_tracker_nodelet_replay_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
