// Deterministic bag replay through the adapter (no master, no sleeps):
// rosbags/handheld_sample.bag (rig_sim, 256x192, 30 Hz, default layout) fed
// frame by frame, the published poses against rig_sim/ground_truth.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "bag_replay.h"
#include "cone_tracker/node/layout.h"
#include "cone_tracker/node/tracker_adapter.h"
#include "handheld_limits.h"

namespace cone_tracker {
namespace {

// The handheld scenario starts with the camera at a bearing of 64 deg around
// the equilateral layout; a user gives the tracker that roughly (3.1.6: the
// 120-degree symmetry cannot be resolved from the image alone).
constexpr double kHeadingPriorDeg = 60.0;

NodeConfig DefaultConfig() {
  NodeConfig c;
  c.layout_file = RIG_MODEL_LAYOUTS_DIR "/default.yaml";
  c.heading_prior_deg = kHeadingPriorDeg;
  c.pose.initial_heading_rad = kHeadingPriorDeg * M_PI / 180.0;
  return c;
}

std::vector<ConeModel> DefaultLayout() {
  std::vector<ConeModel> layout;
  std::string error;
  EXPECT_TRUE(LoadLayoutFile(RIG_MODEL_LAYOUTS_DIR "/default.yaml", &layout, &error)) << error;
  return layout;
}

}  // namespace

TEST(AdapterReplay, HandheldSampleAgainstGroundTruth) {
  const std::vector<ConeModel> layout = DefaultLayout();
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<BagFrame> frames = ReadBag(CONE_TRACKER_ROSBAGS_DIR "/handheld_sample.bag", layout, 6.0);
  ASSERT_EQ(frames.size(), 240u);
  const auto t1 = std::chrono::steady_clock::now();
  TrackerAdapter adapter(DefaultConfig(), layout);
  const auto t2 = std::chrono::steady_clock::now();
  std::map<uint64_t, geometry_msgs::PoseWithCovarianceStamped> poses;
  std::map<FrameStatus, int> statuses;
  for (const BagFrame& f : frames) {
    std::string error;
    ASSERT_TRUE(adapter.SetCameraInfo(*f.info, &error)) << error;
    const FrameResult r = adapter.Process(f.image, std::nullopt);
    ++statuses[r.status];
    if (getenv("CONE_TRACKER_REPLAY_VERBOSE")) {
      const Eigen::Vector3d p = f.truth_T_cones_camera.t;
      std::printf(
          "frame %.3f in_view %d status %s pred %s cones %zu rejected %zu truth bearing %.1f deg dist %.2f %s\n",
          f.image->header.stamp.toSec(), int(f.all_cones_in_view), ToString(r.status), r.prediction_source.c_str(),
          r.segmentation.cones.size(), r.segmentation.rejected.size(), std::atan2(p.y(), p.x()) * 180 / M_PI, p.norm(),
          r.message.c_str());
    }
    ASSERT_TRUE(r.detections) << r.message;
    EXPECT_EQ(r.detections->header.stamp, f.image->header.stamp);
    EXPECT_EQ(r.detections->pose_published, bool(r.pose));
    if (!r.pose) continue;
    EXPECT_EQ(r.pose->header.stamp, f.image->header.stamp);
    EXPECT_EQ(r.pose->header.frame_id, "cones");
    poses[r.pose->header.stamp.toNSec()] = *r.pose;
  }
  const auto t3 = std::chrono::steady_clock::now();
  std::printf("read bag %.2f s, adapter %.2f s, frames %.2f s\n", std::chrono::duration<double>(t1 - t0).count(),
              std::chrono::duration<double>(t2 - t1).count(), std::chrono::duration<double>(t3 - t2).count());
  for (const auto& [s, n] : statuses) std::printf("status %-32s %d frames\n", ToString(s), n);
  const Accuracy a = Evaluate(frames, poses);
  std::printf("ACCURACY adapter replay handheld_sample: %s\n", a.Summary().c_str());
  ExpectHandheldSampleAccuracy(a);
}

}  // namespace cone_tracker
