// Bad input to the nodelet in a manager: each case must leave the nodelet
// running, show up clearly in /diagnostics and publish no pose. Frames come
// from rig_sim's renderer (512x384, the default lens). Between the cases a good
// frame checks that poses still come out, so "no pose" is not vacuous. Also:
// dynamic_reconfigure takes effect, the debug image is built only while
// someone subscribes.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <tf2_msgs/TFMessage.h>
#include <Eigen/Geometry>

#include "cone_tracker/ConeDetections.h"
#include "cone_tracker/testing/vision_frames.h"
#include "nodelet_test_util.h"

namespace cone_tracker {
namespace {

const CameraModel kCamera = rig_model::ThesisCamera().Scaled(0.5);
const Eigen::Vector3d kEye(3.4, 0.6, 1.4), kTarget(0.0, 0.0, 0.3);

sensor_msgs::ImagePtr Frame(const rig_sim::Scene& scene, const rig_sim::TruePose& pose) {
  const SimFrame f = RenderSim(scene, pose, kCamera, 2.0);
  auto img = boost::make_shared<sensor_msgs::Image>();
  img->width = uint32_t(kCamera.width_px), img->height = uint32_t(kCamera.height_px);
  img->encoding = "rgb8", img->step = img->width * 3;
  img->data = f.rgb;
  return img;
}

class BadInput : public testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(rig_.Connect()) << "the nodelet did not subscribe";
    rig_.PublishInfo(CameraInfo(kCamera));
    ASSERT_TRUE(rig_.WaitForFrames(frames_)) << "no diagnostics from the nodelet";  // a status to count from
  }
  // Publishes the image (stamped now unless given) and waits for the diagnostics of that frame.
  const TrackerStatus& Send(const sensor_msgs::ImagePtr& img, const ros::Time& stamp = ros::Time()) {
    img->header.stamp = stamp.isZero() ? ros::Time::now() : stamp;
    img->header.frame_id = "camera_optical";
    stamp_ = img->header.stamp;
    poses_before_ = rig_.status.Value("poses published");
    ++frames_;
    rig_.image_pub.publish(img);
    EXPECT_TRUE(rig_.WaitForFrames(frames_)) << "no diagnostics for frame " << frames_;
    return rig_.status;
  }
  // Decided by the nodelet's own count, not by how long the test waited.
  bool PosePublished() { return rig_.PoseOfFrame(stamp_, poses_before_); }
  // camera_info travels on its own connection: a frame that overtook a new one was judged with the
  // old one (counted as without or with invalid camera_info). Such a frame is sent again.
  const TrackerStatus& SendAfterValidInfo(const std::function<sensor_msgs::ImagePtr()>& frame) {
    for (int attempt = 0;; ++attempt) {
      const double before = InfoProblems(rig_.status);
      const TrackerStatus& s = Send(frame());
      if (InfoProblems(s) == before || attempt == 50) return s;
    }
  }
  static double InfoProblems(const TrackerStatus& s) {
    return s.Value("frames without camera_info") + s.Value("frames with invalid camera_info");
  }
  void ExpectGoodFrameGivesPose() {
    const TrackerStatus& s = SendAfterValidInfo([] { return Frame(rig_sim::DefaultScene(), LookAt(kEye, kTarget)); });
    EXPECT_EQ(s.level, diagnostic_msgs::DiagnosticStatus::OK) << s.message;
    EXPECT_TRUE(PosePublished()) << s.message;
  }
  void ExpectNoPose(const TrackerStatus& s, const std::string& counter, const std::string& text) {
    EXPECT_NE(s.level, diagnostic_msgs::DiagnosticStatus::OK);
    EXPECT_GE(s.Value(counter), 1.0) << counter;
    EXPECT_NE(s.message.find(text), std::string::npos) << "'" << s.message << "' should mention '" << text << "'";
    EXPECT_FALSE(PosePublished()) << s.message;
  }

  NodeletRig rig_;
  ros::Time stamp_;
  double poses_before_ = 0.0;
  static int frames_;  // the nodelet counts frames over all the tests of this process
};
int BadInput::frames_ = 0;

TEST_F(BadInput, EachCaseGivesADiagnosticAndNoPose) {
  ExpectGoodFrameGivesPose();

  auto empty = boost::make_shared<sensor_msgs::Image>();
  empty->encoding = "rgb8";
  ExpectNoPose(Send(empty), "bad images", "image is 0x0 px");

  auto one = boost::make_shared<sensor_msgs::Image>();
  one->width = one->height = 1, one->encoding = "rgb8", one->step = 3, one->data = {255, 100, 0};
  ExpectNoPose(Send(one), "bad images", "image is 1x1 px");

  auto mono = boost::make_shared<sensor_msgs::Image>();
  mono->width = uint32_t(kCamera.width_px), mono->height = uint32_t(kCamera.height_px), mono->encoding = "mono8";
  mono->step = mono->width, mono->data.assign(size_t(mono->step) * mono->height, 128);
  ExpectNoPose(Send(mono), "unsupported encoding frames", "'mono8' is not supported");

  ExpectNoPose(Send(Frame(rig_sim::DefaultScene(), LookAt(kEye, Eigen::Vector3d(9.0, 9.0, 0.0)))),
               "frames with no cones", "no cones found");

  for (size_t n : {1u, 2u}) {
    rig_sim::Scene scene = rig_sim::DefaultScene();
    scene.cones.resize(n);
    ExpectNoPose(Send(Frame(scene, LookAt(kEye, kTarget))), "frames with too few cones",
                 std::to_string(n) + " cone(s) found");
  }

  // Five orange things that are not cones, where the cones would stand.
  rig_sim::Scene clutter;
  clutter.cones.clear();
  clutter.boxes.push_back({Eigen::Vector3d(0.8, 0.0, 0.2), 0.3, Eigen::Vector3d(0.4, 0.3, 0.4), {0.85, 0.18, 0.02}});
  clutter.boxes.push_back({Eigen::Vector3d(-0.4, 0.8, 0.4), 0.0, Eigen::Vector3d(0.3, 0.3, 0.8), {0.85, 0.18, 0.02}});
  clutter.boxes.push_back({Eigen::Vector3d(-0.5, -0.7, 0.15), 0.8, Eigen::Vector3d(0.6, 0.4, 0.3), {0.9, 0.3, 0.02}});
  clutter.patches.push_back({Eigen::Vector2d(1.5, 0.9), 0.2, Eigen::Vector2d(0.5, 0.5), {0.85, 0.18, 0.02}});
  clutter.people.push_back({Eigen::Vector2d(-1.2, -0.1), 1.75, 0.22});
  const TrackerStatus& s = Send(Frame(clutter, LookAt(kEye, kTarget)));
  EXPECT_FALSE(PosePublished()) << s.message;
  EXPECT_NE(s.level, diagnostic_msgs::DiagnosticStatus::OK);
  EXPECT_NE(s.message.find("no pose"), std::string::npos) << s.message;

  ExpectGoodFrameGivesPose();
}

// The default scene with the camera turned until the axis of the leftmost cone is on the image's left edge (the
// other two whole); none when no turn does that.
std::optional<rig_sim::TruePose> ViewWithAConeOnTheLeftEdge() {
  const rig_sim::Scene scene = rig_sim::DefaultScene();
  const Eigen::Vector3d right = (kTarget - kEye).cross(Eigen::Vector3d::UnitZ()).normalized();
  const CameraModel& camera = kCamera;
  for (double shift = 0.0; shift < 4.0; shift += 0.01) {
    const rig_sim::TruePose pose = LookAt(kEye, kTarget + shift * right);  // turning right moves the cones left
    double min_u = 1e9, second_u = 1e9;
    for (const rig_sim::ConeSpec& c : scene.cones) {
      Eigen::Vector2d uv;
      if (!camera.Project(pose.R_cones_camera.transpose() * (c.peak_m() - pose.p_camera_in_cones_m), &uv)) continue;
      if (uv.x() < min_u)
        second_u = min_u, min_u = uv.x();
      else
        second_u = std::min(second_u, uv.x());
    }
    if (min_u > 1.0) continue;
    EXPECT_GT(second_u, 20.0) << "two cones at the border";
    return pose;
  }
  return std::nullopt;
}

TEST_F(BadInput, ConeCutByTheBorder) {
  const std::optional<rig_sim::TruePose> pose = ViewWithAConeOnTheLeftEdge();
  ASSERT_TRUE(pose) << "no view with a cone on the border";
  ExpectNoPose(Send(Frame(rig_sim::DefaultScene(), *pose)), "blobs rejected by gate border", "cone(s) found");
  ExpectGoodFrameGivesPose();
}

TEST_F(BadInput, NanInCameraInfo) {
  sensor_msgs::CameraInfo bad = CameraInfo(kCamera);
  bad.K[0] = std::nan("");
  rig_.PublishInfo(bad);
  // Until the bad camera_info has reached the nodelet (its own connection), frames are judged with the
  // good one: send until one is judged with the bad one.
  for (int attempt = 0; attempt < 50; ++attempt) {
    Send(Frame(rig_sim::DefaultScene(), LookAt(kEye, kTarget)));
    if (rig_.status.Value("frames with invalid camera_info") >= 1.0) break;
  }
  const TrackerStatus& s = rig_.status;
  EXPECT_EQ(s.level, diagnostic_msgs::DiagnosticStatus::ERROR);
  EXPECT_NE(s.message.find("NaN"), std::string::npos) << s.message;
  EXPECT_GE(s.Value("frames with invalid camera_info"), 1.0);
  EXPECT_FALSE(PosePublished());
  rig_.PublishInfo(CameraInfo(kCamera));  // a valid one: tracking resumes
  ExpectGoodFrameGivesPose();
}

TEST_F(BadInput, ReconfigureTakesEffect) {
  ExpectGoodFrameGivesPose();
  ASSERT_TRUE(rig_.Reconfigure({{"hue_min_deg", 180.0}, {"hue_max_deg", 250.0}}));  // blue: no cone pixels
  ExpectNoPose(Send(Frame(rig_sim::DefaultScene(), LookAt(kEye, kTarget))), "frames with no cones", "no cones found");
  ASSERT_TRUE(rig_.Reconfigure({{"hue_min_deg", 0.0}, {"hue_max_deg", 40.107}}));
  ExpectGoodFrameGivesPose();
}

TEST_F(BadInput, DebugImageOnlyWhileSubscribed) {
  ExpectGoodFrameGivesPose();
  EXPECT_EQ(rig_.status.Value("debug images built"), 0.0);
  sensor_msgs::ImageConstPtr debug;
  ros::Subscriber sub = rig_.nh.subscribe<sensor_msgs::Image>("cone_tracker/debug_image", 1,
                                                              [&](const sensor_msgs::ImageConstPtr& m) { debug = m; });
  ASSERT_TRUE(SpinUntil([&] { return sub.getNumPublishers() > 0; }, 60.0));
  // The nodelet may see the new subscriber a little after the test does: frames are sent until a debug
  // image comes (the nodelet builds one per frame while subscribed).
  for (int attempt = 0; attempt < 50 && !debug; ++attempt) {
    ExpectGoodFrameGivesPose();
    if (rig_.status.Value("debug images built") >= 1.0) SpinUntil([&] { return bool(debug); }, 60.0);
  }
  ASSERT_TRUE(debug) << "no debug image while subscribed";
  EXPECT_EQ(debug->width, uint32_t(kCamera.width_px));
  EXPECT_EQ(debug->encoding, "bgr8");
  EXPECT_GE(rig_.status.Value("debug images built"), 1.0);
}

// The prediction comes from tf (pose_ekf's cones -> camera_optical) when it
// reaches the image stamp, and the motion gate (6.4.2) rejects a pose too far
// from it.
TEST_F(BadInput, TfPredictionAndMotionGate) {
  std::map<uint64_t, ConeDetections::ConstPtr> detections;
  ros::Subscriber sub = rig_.nh.subscribe<ConeDetections>(
      "cone_tracker/detections", 10,
      [&](const ConeDetections::ConstPtr& m) { detections[m->header.stamp.toNSec()] = m; });
  ASSERT_TRUE(SpinUntil([&] { return sub.getNumPublishers() > 0; }, 10.0));
  // A plain publisher, to wait for the nodelet's tf listener before sending (a fresh broadcaster
  // would drop the first transform while connecting).
  ros::Publisher tf_pub = rig_.nh.advertise<tf2_msgs::TFMessage>("/tf", 10);
  ASSERT_TRUE(SpinUntil([&] { return tf_pub.getNumSubscribers() > 0; }, 10.0));
  const rig_sim::TruePose truth = LookAt(kEye, kTarget);
  const rig_sim::Scene scene = rig_sim::DefaultScene();
  // One frame with pose_ekf's estimate at its stamp, offset by dp_m from the truth. The stamps are the
  // test's, not the clock's: the tracker's reacquire_after_s (1 s) compares stamps, so the gap it sees
  // between two frames must not grow with the time the test takes between them on a loaded machine.
  // The transform travels on /tf, another connection than the image: if the frame overtook it, the
  // prediction is not "tf" and the pair is sent again (a wait on a condition, not on the clock). The
  // frames are 0.7 s apart: more than prediction_max_age_s (0.5 s), so an older transform is never
  // taken for this one's, less than reacquire_after_s, so the track is never lost in between.
  ros::Time stamp = ros::Time::now();
  // With pan_rad_s != 0, pose_ekf lags the image instead: its two newest transforms are 30 and 10 ms older than the
  // frame, of a camera panning at that rate about its y axis that reaches the truth at the frame's stamp.
  auto frame_with_tf = [&](const Eigen::Vector3d& dp_m, double pan_rad_s = 0.0) -> ConeDetections::ConstPtr {
    for (int attempt = 0; attempt < 50; ++attempt) {
      stamp += ros::Duration(0.7);
      tf2_msgs::TFMessage msg;
      for (double dt_s : pan_rad_s == 0.0 ? std::vector<double>{0.0} : std::vector<double>{-0.03, -0.01}) {
        geometry_msgs::TransformStamped t;
        t.header.stamp = stamp + ros::Duration(dt_s), t.header.frame_id = "cones", t.child_frame_id = "camera_optical";
        const Eigen::Quaterniond q(truth.R_cones_camera *
                                   Eigen::AngleAxisd(pan_rad_s * dt_s, Eigen::Vector3d::UnitY()));
        t.transform.rotation.w = q.w(), t.transform.rotation.x = q.x(), t.transform.rotation.y = q.y();
        t.transform.rotation.z = q.z();
        const Eigen::Vector3d p = truth.p_camera_in_cones_m + dp_m;
        t.transform.translation.x = p.x(), t.transform.translation.y = p.y(), t.transform.translation.z = p.z();
        msg.transforms.push_back(t);
      }
      tf_pub.publish(msg);
      SpinUntil([] { return false; }, 0.3);  // usually enough for the nodelet's tf buffer; if not, sent again
      Send(Frame(scene, truth), stamp);
      if (!SpinUntil([&] { return detections.count(stamp.toNSec()) > 0; }, 60.0)) return nullptr;
      if (detections[stamp.toNSec()]->prediction_source == "tf") return detections[stamp.toNSec()];
    }
    return nullptr;
  };

  ConeDetections::ConstPtr d = frame_with_tf(Eigen::Vector3d::Zero());
  ASSERT_TRUE(d);
  EXPECT_EQ(d->prediction_source, "tf");
  EXPECT_TRUE(d->pose_published) << d->status;
  EXPECT_TRUE(PosePublished());
  EXPECT_TRUE(d->motion_checked);
  EXPECT_TRUE(d->motion_passed);
  EXPECT_LT(d->translation_change_m, 0.1);
  EXPECT_TRUE(d->chi2_passed);
  EXPECT_EQ(d->chi2_dof, 12);  // 3 cones x 3 points x 2 - 6
  EXPECT_GT(d->chi2_cdf, 0.0);
  EXPECT_LT(d->chi2_cdf, 0.999);
  EXPECT_EQ(d->accepted_count, 3);
  // Each accepted blob carries the id of the cone whose peak projects onto it (the tf prediction fixes
  // the 120-degree ambiguity).
  const CameraModel& camera = kCamera;
  std::set<int> ids;
  for (int i = 0; i < d->accepted_count; ++i) {
    const DetectedCone& c = d->detections[size_t(i)];
    ids.insert(c.cone_id);
    ASSERT_GE(c.cone_id, 0);
    Eigen::Vector2d uv;
    ASSERT_TRUE(camera.Project(
        truth.R_cones_camera.transpose() * (scene.cones[size_t(c.cone_id)].peak_m() - truth.p_camera_in_cones_m), &uv));
    EXPECT_LT((uv - Eigen::Vector2d(c.peak_px[0], c.peak_px[1])).norm(), 6.0) << "cone " << c.cone_id;
    EXPECT_TRUE(c.failed_gate_names.empty());
    EXPECT_GT(c.area_px, 30.0);
  }
  EXPECT_EQ(ids, (std::set<int>{0, 1, 2}));
  EXPECT_GE(rig_.status.Value("tf predictions used"), 1.0);

  // pose_ekf 0.3 m off along the line of sight (the cones still match within max_assignment_px).
  ASSERT_TRUE(rig_.Reconfigure({{"max_translation_change_m", 0.2}}));
  const Eigen::Vector3d forward = truth.R_cones_camera.col(2);
  d = frame_with_tf(0.3 * forward);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->prediction_source, "tf");
  EXPECT_FALSE(d->pose_published);
  EXPECT_TRUE(d->motion_checked);
  EXPECT_FALSE(d->motion_passed);
  EXPECT_NEAR(d->translation_change_m, 0.3, 0.1);
  EXPECT_EQ(d->pose_rejected_by_names, std::vector<std::string>{"motion"});
  EXPECT_NE(rig_.status.message.find("motion gate"), std::string::npos) << rig_.status.message;
  EXPECT_GE(rig_.status.Value("rejected by motion gate"), 1.0);
  EXPECT_FALSE(PosePublished());
  ASSERT_TRUE(rig_.Reconfigure({{"max_translation_change_m", 0.5}}));

  // pose_ekf 10 ms behind a camera panning at 3 rad/s: its newest pose is 1.7 deg off, beyond a 0.5 deg motion gate.
  // Carried on to the image stamp at the rate of the two, it is the truth, and the pose passes.
  ASSERT_TRUE(rig_.Reconfigure({{"max_rotation_change_deg", 0.5}}));
  const double extrapolated = rig_.status.Value("tf predictions extrapolated to the image stamp");
  d = frame_with_tf(Eigen::Vector3d::Zero(), 3.0);
  ASSERT_TRUE(d);
  EXPECT_TRUE(d->motion_passed) << d->status;
  EXPECT_LT(d->rotation_change_deg, 0.3);
  EXPECT_TRUE(d->pose_published) << d->status;
  ASSERT_TRUE(SpinUntil(
      [&] { return rig_.status.Value("tf predictions extrapolated to the image stamp") > extrapolated; }, 10.0));
  ASSERT_TRUE(rig_.Reconfigure({{"max_rotation_change_deg", 30.0}}));
}

// The two-cone start from imu/data_raw: the IMU mounted turned against the camera (a static tf), a NaN sample
// refused and counted, then gravity around the stamp of a frame with two cones and no prediction reaches the start.
TEST_F(BadInput, TwoConeStartFromTheImu) {
  ros::Publisher imu_pub = rig_.nh.advertise<sensor_msgs::Imu>("imu/data_raw", 100);
  ros::Publisher static_pub = rig_.nh.advertise<tf2_msgs::TFMessage>("/tf_static", 1, /*latch=*/true);
  ASSERT_TRUE(SpinUntil([&] { return imu_pub.getNumSubscribers() > 0 && static_pub.getNumSubscribers() > 0; }, 10.0));
  const Eigen::Quaterniond q_camera_imu(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()) *
                                        Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
  tf2_msgs::TFMessage mount;
  geometry_msgs::TransformStamped t;
  t.header.stamp = ros::Time::now(), t.header.frame_id = "camera_optical", t.child_frame_id = "rig_imu";
  t.transform.rotation.w = q_camera_imu.w(), t.transform.rotation.x = q_camera_imu.x();
  t.transform.rotation.y = q_camera_imu.y(), t.transform.rotation.z = q_camera_imu.z();
  mount.transforms.push_back(t);
  static_pub.publish(mount);

  // Two whole cones and one cut by the border (refused), with no prediction: the stamp far after every earlier
  // frame and transform. The default layout's three cones are alike and evenly spaced, so its rotations fit
  // the two cones alike: the start refuses the frame as ambiguous ("fit alike"). That needs gravity turned into
  // the camera the right way round: turned the wrong way, no pairing fits ("no pair of layout cones fits").
  const std::optional<rig_sim::TruePose> view = ViewWithAConeOnTheLeftEdge();
  ASSERT_TRUE(view);
  const rig_sim::TruePose& truth = *view;
  const ros::Time stamp = ros::Time::now() + ros::Duration(100.0);
  const Eigen::Vector3d up_camera = truth.R_cones_camera.transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d f_imu = q_camera_imu.conjugate() * (9.81 * up_camera);
  auto sample = [&](const ros::Time& at, const Eigen::Vector3d& f) {
    sensor_msgs::Imu m;
    m.header.stamp = at, m.header.frame_id = "rig_imu";
    m.linear_acceleration.x = f.x(), m.linear_acceleration.y = f.y(), m.linear_acceleration.z = f.z();
    imu_pub.publish(m);
  };
  // The static tf may reach the nodelet after the first samples (refused: no tf yet): a sample a second before the
  // stamp until one is kept, then the window around the stamp.
  const auto kept = [&] { return rig_.status.Value("IMU samples for gravity"); };
  const double kept_before = kept();
  ASSERT_TRUE(SpinUntil([&] { return sample(stamp - ros::Duration(1.0), f_imu), kept() > kept_before; }, 30.0));
  const double kept_tf = kept();
  for (int i = -5; i <= 5; ++i) sample(stamp + ros::Duration(0.01 * i), f_imu);
  ASSERT_TRUE(SpinUntil([&] { return kept() >= kept_tf + 11.0; }, 30.0));
  const double refused_before = rig_.status.Value("IMU samples refused (non-finite, or no tf to camera_frame)");
  sample(stamp + ros::Duration(0.2), Eigen::Vector3d(NAN, 0.0, 9.81));
  ASSERT_TRUE(SpinUntil(
      [&] { return rig_.status.Value("IMU samples refused (non-finite, or no tf to camera_frame)") > refused_before; },
      30.0));

  std::map<uint64_t, ConeDetections::ConstPtr> detections;
  ros::Subscriber sub = rig_.nh.subscribe<ConeDetections>(
      "cone_tracker/detections", 10,
      [&](const ConeDetections::ConstPtr& m) { detections[m->header.stamp.toNSec()] = m; });
  ASSERT_TRUE(SpinUntil([&] { return sub.getNumPublishers() > 0; }, 10.0));
  const double refused = rig_.status.Value("two-cone starts refused (no pair of layout cones fits, or two fit alike)");
  const double without = rig_.status.Value("two-cone frames without gravity (no imu/data_raw around the stamp)");
  const TrackerStatus& s = Send(Frame(rig_sim::DefaultScene(), truth), stamp);
  EXPECT_FALSE(PosePublished()) << s.message;
  EXPECT_EQ(s.Value("two-cone starts refused (no pair of layout cones fits, or two fit alike)"), refused + 1.0);
  EXPECT_EQ(s.Value("two-cone frames without gravity (no imu/data_raw around the stamp)"), without);
  ASSERT_TRUE(SpinUntil([&] { return detections.count(stamp.toNSec()) > 0; }, 60.0));
  const ConeDetections& d = *detections[stamp.toNSec()];
  EXPECT_EQ(d.prediction_source, "two_cones_gravity");
  EXPECT_EQ(d.accepted_count, 2);
  EXPECT_NE(d.status.find("fit alike"), std::string::npos) << d.status;
}

}  // namespace
}  // namespace cone_tracker

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "cone_tracker_bad_input_test");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
