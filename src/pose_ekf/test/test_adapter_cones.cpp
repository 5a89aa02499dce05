// cone_tracker/observations through the adapter (no master): the layout file from ~layout_file
// through rig_model's parser, the message checks (NaN pixels, unknown cone ids, intrinsics, frame,
// stamps older than the buffer), each counted and named, and the new parameters.
#include <unistd.h>

#include <gtest/gtest.h>

#include <fstream>
#include <limits>
#include <random>

#include "pose_ekf/node/pose_ekf_adapter.h"
#include "pose_ekf/testing/synthetic_cones.h"
#include "rig_model/layout.h"
#include "ros_messages.h"

namespace pose_ekf_test {
namespace {

using pose_ekf::AddResult;

const std::string kDefaultLayout = std::string(POSE_EKF_SOURCE_DIR) + "/../rig_model/config/layouts/default.yaml";

std::string Write(const std::string& name, const std::string& text) {
  const std::string path = "/tmp/" + name + "_" + std::to_string(getpid()) + ".yaml";
  std::ofstream(path) << text;
  return path;
}

pose_ekf::NodeConfig WithLayout() {
  pose_ekf::NodeConfig c;
  c.camera_update = static_cast<int>(pose_ekf::CameraUpdate::kCones);  // opt-in (the default is pose)
  c.ekf.camera_update = pose_ekf::CameraUpdate::kCones;
  c.layout_file = kDefaultLayout;
  pose_ekf::LoadLayout(&c);
  return c;
}

TEST(AdapterCones, NewParametersAndTheLayoutFileLoad) {
  const pose_ekf::NodeConfig c =
      pose_ekf::LoadConfigFile(Write("pose_ekf_cone_keys",
                                     "camera_update: pose\ncone_gate_probability: 0.999\ncone_joint_probability: 0.99\n"
                                     "reacquire_sigma_p_m: 0.3\nreacquire_min_cones: 3\nlayout_file: " +
                                         kDefaultLayout + "\n"));
  EXPECT_EQ(c.ekf.camera_update, pose_ekf::CameraUpdate::kPose);
  EXPECT_EQ(c.ekf.cone_gate_probability, 0.999);
  EXPECT_EQ(c.ekf.cone_joint_probability, 0.99);
  EXPECT_EQ(c.ekf.reacquire_sigma_p_m, 0.3);
  EXPECT_EQ(c.ekf.reacquire_min_cones, 3);
  ASSERT_EQ(c.layout_cones.size(), 3u);
  const auto expected = pose_ekf::ConeGeometries(rig_model::DefaultLayout());
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_LT((c.layout_cones[i].base_m - expected[i].base_m).norm(), 1e-12);
    EXPECT_EQ(c.layout_cones[i].height_m, expected[i].height_m);
  }
  EXPECT_EQ(pose_ekf::NodeConfig{}.ekf.camera_update, pose_ekf::CameraUpdate::kPose);  // the default (opt-in cones)
  EXPECT_TRUE(pose_ekf::NodeConfig{}.layout_file.empty());
}

TEST(AdapterCones, BadLayoutFileOrValuesAreRefusedNamingThem) {
  auto message = [](const std::string& yaml) {
    try {
      pose_ekf::LoadConfigFile(Write("pose_ekf_cone_bad", yaml));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string missing = message("layout_file: /nonexistent/cones.yaml\n");
  EXPECT_NE(missing.find("layout_file"), std::string::npos) << missing;
  EXPECT_NE(missing.find("/nonexistent/cones.yaml"), std::string::npos) << missing;
  const std::string bad = Write("pose_ekf_bad_layout", "cones:\n  - {x_m: 1.0, y_m: 0.0, hieght_m: 0.7}\n");
  const std::string typo = message("layout_file: " + bad + "\n");
  EXPECT_NE(typo.find(bad), std::string::npos) << typo;
  EXPECT_NE(typo.find("hieght_m"), std::string::npos) << typo;
  EXPECT_NE(message("camera_update: both\n").find("camera_update"), std::string::npos);
  EXPECT_NE(message("cone_gate_probability: 0\n").find("cone_gate_probability"), std::string::npos);
  EXPECT_NE(message("reacquire_sigma_p_m: -1\n").find("reacquire_sigma_p_m"), std::string::npos);
  EXPECT_NE(message("reacquire_min_cones: 0\n").find("reacquire_min_cones"), std::string::npos);
}

// A tracking adapter: initialised from the rig's first pose, then one IMU sample.
struct Tracking {
  pose_ekf::PoseEkfAdapter adapter{WithLayout()};
  std::vector<Event> events;
  std::mt19937 rng{3};
  Tracking() {
    RigSimConfig sim;
    sim.duration_s = 0.5;
    events = GenerateRig(sim);
    std::string why;
    EXPECT_EQ(adapter.HandleCamera(CameraMsg(events[0].camera), &why), AddResult::kInitialized) << why;
  }
  // The observations of camera event `k` (k-th camera frame).
  cone_tracker::ConeObservations Frame(int k) {
    int seen = 0;
    for (const Event& e : events) {
      if (!e.is_camera) {
        if (seen > k) break;
        continue;
      }
      if (seen++ == k) {
        for (const Event& i : events) {
          if (!i.is_camera && i.stamp_s < e.stamp_s && i.stamp_s > adapter.buffer().filter().state().stamp_s) {
            std::string why;
            adapter.HandleImu(ImuMsg(i.imu), kQCameraImu, &why);
          }
        }
        return ObservationsMsg(
            ObserveCones(e.stamp_s, e.truth.T_cones_camera, DefaultCones(), {0, 1, 2}, DefaultIntrinsics(), 1.0, &rng));
      }
    }
    ADD_FAILURE() << "no camera frame " << k;
    return {};
  }
};

TEST(AdapterCones, GoodObservationsAreFused) {
  Tracking t;
  std::string why;
  EXPECT_EQ(t.adapter.HandleObservations(t.Frame(1), &why), AddResult::kApplied) << why;
  EXPECT_TRUE(why.empty()) << why;
  EXPECT_EQ(t.adapter.buffer().counters().cones_applied, 3u);
  EXPECT_EQ(t.adapter.buffer().counters().cone_frames_applied, 1u);
  // The frame carries the whole layout, for the filter's lone-cone ambiguity test.
  pose_ekf::ConeFrame f;
  int nan = 0, invalid = 0;
  ASSERT_EQ(pose_ekf::ConeFrameFromMsg(t.Frame(2), t.adapter.config().camera_frame, t.adapter.config().layout_cones, &f,
                                       &why, &nan, &invalid),
            pose_ekf::ConversionResult::kOk)
      << why;
  EXPECT_EQ(f.layout.size(), t.adapter.config().layout_cones.size());
  // And the orange regions in undistorted pixels, as boxes out to the pixels' edges; boxes in raw pixels
  // (do_rectify false) do not match the model's pixels and are left out.
  cone_tracker::ConeObservations msg = t.Frame(3);
  msg.orange.resize(2);
  msg.orange[0].x_offset = 10, msg.orange[0].y_offset = 20, msg.orange[0].width = 5, msg.orange[0].height = 8;
  msg.orange[0].do_rectify = true;
  msg.orange[1] = msg.orange[0];
  msg.orange[1].do_rectify = false;
  ASSERT_EQ(pose_ekf::ConeFrameFromMsg(msg, t.adapter.config().camera_frame, t.adapter.config().layout_cones, &f, &why,
                                       &nan, &invalid),
            pose_ekf::ConversionResult::kOk)
      << why;
  ASSERT_EQ(f.orange_px.size(), 1u);
  EXPECT_DOUBLE_EQ(f.orange_px[0].u_min, 9.5);
  EXPECT_DOUBLE_EQ(f.orange_px[0].u_max, 14.5);
  EXPECT_DOUBLE_EQ(f.orange_px[0].v_min, 19.5);
  EXPECT_DOUBLE_EQ(f.orange_px[0].v_max, 27.5);
}

TEST(AdapterCones, BadConesAreLeftOutCountedAndNamed) {
  Tracking t;
  std::string why;
  cone_tracker::ConeObservations msg = t.Frame(1);
  msg.cones[1].mid_px[0] = std::numeric_limits<double>::quiet_NaN();
  msg.cones[2].cone_id = 7;  // not in the 3-cone layout
  EXPECT_EQ(t.adapter.HandleObservations(msg, &why), AddResult::kApplied);
  EXPECT_EQ(why, "cone_tracker/observations: cones[1] (cone_id 1): mid_px is not finite");
  EXPECT_EQ(t.adapter.cones_refused_nan(), 1u);
  EXPECT_EQ(t.adapter.cones_refused_invalid(), 1u);
  EXPECT_EQ(t.adapter.buffer().counters().cones_applied, 1u);  // cone 0 alone
  msg = t.Frame(2);
  msg.cones[0].cone_id = -1;
  msg.cones[1].cone_id = 3;
  msg.cones[2].base_cov_px2[0] = -1.0;
  why.clear();
  EXPECT_EQ(t.adapter.HandleObservations(msg, &why), AddResult::kRejectedInvalid);
  EXPECT_EQ(why, "cone_tracker/observations: cones[0] (cone_id -1): cone_id is not in the layout (3 cones)");
  EXPECT_EQ(t.adapter.cones_refused_invalid(), 4u);
  EXPECT_EQ(t.adapter.invalid_rejected(), 4u);
  EXPECT_EQ(t.adapter.nan_rejected(), 1u);
}

TEST(AdapterCones, BadIntrinsicsFrameOrNoLayoutRefuseTheMessage) {
  Tracking t;
  std::string why;
  cone_tracker::ConeObservations msg = t.Frame(1);
  msg.fx = 0.0;
  EXPECT_EQ(t.adapter.HandleObservations(msg, &why), AddResult::kRejectedInvalid);
  EXPECT_NE(why.find("cone_tracker/observations: intrinsics fx 0"), std::string::npos) << why;
  msg.fx = 800.0;
  msg.fy = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(t.adapter.HandleObservations(msg, &why), AddResult::kRejectedNonFinite);
  msg.fy = 800.0;
  msg.header.frame_id = "camera";
  EXPECT_EQ(t.adapter.HandleObservations(msg, &why), AddResult::kRejectedInvalid);
  EXPECT_EQ(why, "cone_tracker/observations: header.frame_id is 'camera', expected 'camera_optical'");
  EXPECT_EQ(t.adapter.observations_rejected(), 3u);
  EXPECT_EQ(t.adapter.buffer().counters().cones_applied, 0u);
  pose_ekf::PoseEkfAdapter no_layout{pose_ekf::NodeConfig{}};
  EXPECT_EQ(no_layout.HandleObservations(t.Frame(1), &why), AddResult::kRejectedInvalid);
  EXPECT_NE(why.find("~layout_file is not set"), std::string::npos) << why;
}

// A lone cone not fused by the re-acquisition rules: the warning says which rule, not "no cone passed the gates".
TEST(AdapterCones, ALoneConeNotFusedWhileReacquiringSaysWhy) {
  Tracking t;
  cone_tracker::ConeObservations lone = t.Frame(1);
  lone.cones.resize(1);
  pose_ekf::NodeConfig c = WithLayout();
  c.ekf.reacquire_sigma_p_m = 1e-6;  // re-acquisition is due from the start
  c.ekf.reacquire_min_cones = 2;
  pose_ekf::PoseEkfAdapter a{c};
  std::string why;
  ASSERT_EQ(a.HandleCamera(CameraMsg(t.events[0].camera), &why), AddResult::kInitialized) << why;
  why.clear();
  EXPECT_EQ(a.HandleObservations(lone, &why), AddResult::kGated);
  EXPECT_NE(why.find("fewer than reacquire_min_cones"), std::string::npos) << why;
  EXPECT_EQ(a.buffer().counters().cone_frames_too_few, 1u);
}

TEST(AdapterCones, StampsOlderThanTheBufferAreDroppedAndCounted) {
  Tracking t;
  std::string why;
  const cone_tracker::ConeObservations old = t.Frame(1);
  t.Frame(14);  // the IMU up to 0.47 s: frame 1 (0.033 s) is now older than max_delay_s
  EXPECT_EQ(t.adapter.HandleObservations(old, &why), AddResult::kDroppedLate);
  EXPECT_EQ(why, "cone_tracker/observations: observations older than max_delay_s (or the filter's start)");
  EXPECT_EQ(t.adapter.buffer().counters().cone_frames_dropped_late, 1u);
  EXPECT_EQ(t.adapter.buffer().counters().cones_applied, 0u);
  // Before the first pose: not fused (a pose starts the filter), counted.
  pose_ekf::PoseEkfAdapter fresh{WithLayout()};
  EXPECT_EQ(fresh.HandleObservations(old, &why), AddResult::kWaitingForCamera);
  EXPECT_EQ(fresh.buffer().counters().cone_frames_before_start, 1u);
}

}  // namespace
}  // namespace pose_ekf_test
