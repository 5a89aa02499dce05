// Deterministic bag replay through the adapter (no master, no sleeps):
// rosbags/handheld_sample.bag (rig_sim, 256x192, 30 Hz, default layout) fed
// frame by frame, the published poses against rig_sim/ground_truth.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <Eigen/Geometry>

#include "bag_replay.h"
#include "cone_tracker/node/layout.h"
#include "cone_tracker/node/tracker_adapter.h"
#include "handheld_limits.h"
#include "pose_math/rotation.h"

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

namespace cone_tracker {
namespace {

// The layout cone a detection truly is: the one whose true peak and base
// project nearest to it (rig_sim's ground truth, undistorted pixels).
int TrueCone(const ConeObservation& o, const BagFrame& f, const std::vector<ConeModel>& layout, double* dist_px) {
  const pose_math::Pose T = pose_math::Invert(f.truth_T_cones_camera);
  const auto& K = f.info->K;
  auto project = [&](const Eigen::Vector3d& p_cones) {
    const Eigen::Vector3d p = pose_math::Transform(T, p_cones);
    return Eigen::Vector2d(K[0] * p.x() / p.z() + K[2], K[4] * p.y() / p.z() + K[5]);
  };
  int best = -1;
  *dist_px = INFINITY;
  for (size_t c = 0; c < layout.size(); ++c) {
    const auto pts = CorrectedModelPoints(layout[c], f.truth_T_cones_camera.t);
    if (pose_math::Transform(T, pts[2]).z() < 0.1) continue;
    const double e = 0.5 * ((project(pts[0]) - Eigen::Vector2d(o.peak_px[0], o.peak_px[1])).norm() +
                            (project(pts[2]) - Eigen::Vector2d(o.base_px[0], o.base_px[1])).norm());
    if (e < *dist_px) *dist_px = e, best = int(c);
  }
  return best;
}

struct ObservationTally {
  int frames_few = 0, few_observed = 0, messages = 0, cones = 0, wrong = 0, unobserved_without_prediction = 0;
};

// pose_ekf's tf stand-in: the truth a few centimetres and half a degree off.
pose_math::Pose Perturbed(const pose_math::Pose& T_cones_camera) {
  pose_math::Pose T = T_cones_camera;
  T.t += Eigen::Vector3d(0.03, -0.02, 0.02);
  const Eigen::Matrix3d dR = Eigen::AngleAxisd(0.5 * M_PI / 180.0, Eigen::Vector3d(1, -1, 2).normalized()).matrix();
  T.q = pose_math::QuatFromRotation(pose_math::RotationFromQuat(T.q) * dR);
  return T;
}

ObservationTally ReplayObservations(const std::string& bag, const std::vector<BagFrame>& frames,
                                    const std::vector<ConeModel>& layout, bool tf_prediction) {
  EXPECT_FALSE(frames.empty());
  NodeConfig config = DefaultConfig();
  TrackerAdapter adapter(config, layout);
  ObservationTally t;
  for (const BagFrame& f : frames) {
    std::string error;
    EXPECT_TRUE(adapter.SetCameraInfo(*f.info, &error)) << error;
    const FrameResult r =
        adapter.Process(f.image, tf_prediction ? std::optional(Perturbed(f.truth_T_cones_camera)) : std::nullopt);
    const size_t n = r.segmentation.cones.size();
    if (n == 1 || n == 2) {
      ++t.frames_few;
      t.few_observed += bool(r.observations);
      if (!r.observations && getenv("CONE_TRACKER_REPLAY_VERBOSE"))
        std::printf(
            "frame %.3f: %zu cone(s) unobserved: %zu candidates, %d ambiguous, conflict %d, too many %d, pose %s\n",
            f.image->header.stamp.toSec(), n, r.association.candidates.size(), r.association.ambiguous,
            int(r.association.conflict), int(r.association.too_many), ToString(r.status));
    }
    if (!r.observations) {
      t.unobserved_without_prediction += n > 0 && r.prediction_source == "none";
      continue;
    }
    EXPECT_NE(r.prediction_source == "none" && !r.pose, true) << "observations without a pose or a prediction";
    const ConeObservations& m = *r.observations;
    ++t.messages;
    EXPECT_EQ(m.header.stamp, f.image->header.stamp);
    EXPECT_EQ(m.header.frame_id, f.image->header.frame_id.empty() ? "camera_optical" : f.image->header.frame_id);
    EXPECT_EQ(m.fx, f.info->K[0]);
    EXPECT_EQ(m.fy, f.info->K[4]);
    EXPECT_EQ(m.cx, f.info->K[2]);
    EXPECT_EQ(m.cy, f.info->K[5]);
    EXPECT_FALSE(m.cones.empty());
    for (const ConeObservation& o : m.cones) {
      ++t.cones;
      double dist = 0;
      const int truth = TrueCone(o, f, layout, &dist);
      if (truth != o.cone_id) {
        ++t.wrong;
        ADD_FAILURE() << "frame " << f.image->header.stamp << ": cone " << o.cone_id << " is truly " << truth << " ("
                      << dist << " px) source " << r.observation_source;
      }
      for (const auto& c : {o.peak_cov_px2, o.mid_cov_px2, o.base_cov_px2}) {
        EXPECT_EQ(c[1], c[2]);
        EXPECT_GT(c[0], 0.0);
        EXPECT_GT(c[0] * c[3] - c[1] * c[2], 0.0);
      }
    }
  }
  std::printf(
      "OBSERVATIONS %s tf_prediction %d: %d messages, %d cones, %d wrong ids; %d/%d frames with 1-2 cones "
      "observed; %d frames with cones unobserved for want of a prediction\n",
      bag.c_str(), int(tf_prediction), t.messages, t.cones, t.wrong, t.few_observed, t.frames_few,
      t.unobserved_without_prediction);
  return t;
}

}  // namespace

// Frames with one or two cones in view give observations with the true ids
// when pose_ekf's prediction is there; without any prediction none do.
// Measured: 57 of 57 (handheld) and 158 of 161 (look_away) frames with 1-2
// cones observed, no wrong id; the rest are ambiguous (the default layout's
// identical cones). Before overlaps within the prediction's spread kept their
// cones (associate.cpp): 56 of 57 and 152 of 161.
TEST(AdapterReplay, ObservationsCarryTheTrueConeIds) {
  const std::vector<ConeModel> layout = DefaultLayout();
  const std::string handheld = CONE_TRACKER_ROSBAGS_DIR "/handheld_sample.bag";
  const std::string look_away = CONE_TRACKER_ROSBAGS_DIR "/look_away_sample.bag";
  const std::vector<BagFrame> handheld_frames = ReadBag(handheld, layout, 6.0);
  const ObservationTally with = ReplayObservations(handheld, handheld_frames, layout, true);
  EXPECT_EQ(with.wrong, 0);
  EXPECT_GT(with.frames_few, 0);
  EXPECT_GE(with.few_observed, with.frames_few * 9 / 10);
  const ObservationTally look = ReplayObservations(look_away, ReadBag(look_away, layout, 6.0), layout, true);
  EXPECT_EQ(look.wrong, 0);
  EXPECT_GE(look.few_observed, look.frames_few * 9 / 10);
  const ObservationTally own = ReplayObservations(handheld, handheld_frames, layout, false);
  EXPECT_EQ(own.wrong, 0);
  EXPECT_LE(own.messages, with.messages);
}

}  // namespace cone_tracker
