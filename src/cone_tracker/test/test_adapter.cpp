// The adapter on rig_sim frames: encodings, camera_info validation, size
// mismatch, time going back, reconfigure, the heading prior, the pose message.
#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "cone_tracker/node/layout.h"
#include "cone_tracker/node/tracker_adapter.h"
#include "cone_tracker/testing/vision_frames.h"
#include "nodelet_test_util.h"
#include "pose_math/covariance.h"
#include "pose_math/rotation.h"
#include "rig_model/ros/conversions.h"

namespace cone_tracker {
namespace {

const CameraModel kCamera = rig_model::ThesisCamera().Scaled(0.5);
const Eigen::Vector3d kEye(3.4, 0.6, 1.4), kTarget(0.0, 0.0, 0.3);

std::vector<ConeModel> Layout() {
  std::vector<ConeModel> layout;
  std::string error;
  EXPECT_TRUE(LoadLayoutFile(RIG_MODEL_LAYOUTS_DIR "/default.yaml", &layout, &error)) << error;
  return layout;
}

NodeConfig Config(double heading_prior_deg) {
  NodeConfig c;
  c.layout_file = RIG_MODEL_LAYOUTS_DIR "/default.yaml";
  c.heading_prior_deg = heading_prior_deg;
  c.pose.initial_heading_rad = heading_prior_deg * M_PI / 180.0;
  return c;
}

// The rendered frame in the given encoding (rgb8, bgr8 or a bayer pattern).
sensor_msgs::ImagePtr Frame(const std::string& encoding, double stamp_s,
                            const rig_sim::Scene& scene = rig_sim::DefaultScene(),
                            const rig_sim::TruePose& pose = LookAt(kEye, kTarget)) {
  const SimFrame f = RenderSim(scene, pose, kCamera, 1.0);
  auto img = boost::make_shared<sensor_msgs::Image>();
  img->header.stamp.fromSec(stamp_s);
  img->width = uint32_t(kCamera.width_px), img->height = uint32_t(kCamera.height_px), img->encoding = encoding;
  const cv::Mat rgb(kCamera.height_px, kCamera.width_px, CV_8UC3, const_cast<uint8_t*>(f.rgb.data()));
  cv::Mat out;
  if (encoding == "rgb8") {
    out = rgb;
  } else if (encoding == "bgr8") {
    cv::cvtColor(rgb, out, cv::COLOR_RGB2BGR);
  } else {  // sample the colour filter array of the pattern named in the encoding
    const std::string pattern = encoding.substr(6, 4);  // "bayer_rggb8" -> "rggb"
    out.create(rgb.rows, rgb.cols, CV_8UC1);
    for (int y = 0; y < rgb.rows; ++y)
      for (int x = 0; x < rgb.cols; ++x) {
        const char c = pattern[size_t(2 * (y % 2) + (x % 2))];
        out.at<uint8_t>(y, x) = rgb.at<cv::Vec3b>(y, x)[c == 'r' ? 0 : c == 'g' ? 1 : 2];
      }
  }
  img->step = uint32_t(out.step[0]);
  img->data.assign(out.data, out.data + out.step[0] * size_t(out.rows));
  return img;
}

pose_math::Pose Truth() {
  const rig_sim::TruePose t = LookAt(kEye, kTarget);
  pose_math::Pose T;
  T.q = pose_math::QuatFromRotation(t.R_cones_camera);
  T.t = t.p_camera_in_cones_m;
  return T;
}

class Adapter : public testing::Test {
 protected:
  Adapter() : adapter_(Config(std::atan2(kEye.y(), kEye.x()) * 180.0 / M_PI), Layout()) {
    std::string error;
    EXPECT_TRUE(adapter_.SetCameraInfo(CameraInfo(kCamera), &error)) << error;
  }
  TrackerAdapter adapter_;
};

// Every segmentation gate the vision core can set has a name in the
// diagnostics and the detections message.
TEST(GateNames, EverySegmentationGateIsNamed) {
  for (uint32_t bit = 1; bit <= kGateShape; bit <<= 1)
    EXPECT_EQ(SegmentationGateNames(bit).size(), 1u) << "gate bit " << bit << " has no name";
}

// Every encoding reaches the core and gives the same cones. Plain cones (same size and layout, no
// white collars): the demosaiced colour fringes at collars disturb the segmentation on some
// patterns, and this test is about the encodings. The chi-square gate at sigma_px = 1 px may still
// reject a Bayer frame's pose (the thin tip suffers in the mosaic), so for Bayer the solver's pose
// is checked rather than the published one.
TEST_F(Adapter, EveryEncodingGivesThePose) {
  double stamp = 1.0;
  // The outline gate would reject a cone whose demosaiced edges fringe (a segmentation matter).
  SegmenterConfig seg = adapter_.config().segmenter;
  seg.reject_bad_outline = false;
  adapter_.Reconfigure(seg, adapter_.config().pose, adapter_.config().debug);
  const rig_sim::Scene plain = rig_sim::EquilateralScene(1.5, 0.71, rig_sim::ConeStyle::kPlain);
  const pose_math::Pose truth = Truth();
  std::vector<ConeDetection> reference;
  for (const std::string enc : {"rgb8", "bgr8", "bayer_rggb8", "bayer_bggr8", "bayer_gbrg8", "bayer_grbg8"}) {
    adapter_.ClearTrack();  // each encoding solves from scratch
    const FrameResult r = adapter_.Process(Frame(enc, stamp += 1.0, plain), std::nullopt);
    ASSERT_TRUE(r.detections) << enc << ": " << r.message;
    ASSERT_EQ(r.detections->accepted_count, 3) << enc;
    ASSERT_TRUE(r.cone_pose.pnp.ok) << enc << ": " << r.message;
    if (enc.rfind("bayer", 0) != 0) {
      EXPECT_EQ(r.status, FrameStatus::kPose) << enc << ": " << r.message;
    }
    if (reference.empty()) reference = r.segmentation.cones;
    for (size_t i = 0; i < 3; ++i) {
      EXPECT_LT((r.segmentation.cones[i].base_px - reference[i].base_px).norm(), 2.0) << enc;
      EXPECT_LT((r.segmentation.cones[i].peak_px - reference[i].peak_px).norm(), 12.0) << enc;
    }
    const pose_math::Pose est = pose_math::Invert(r.cone_pose.pnp.T_camera_model);
    EXPECT_LT((est.t - truth.t).norm(), enc == "rgb8" || enc == "bgr8" ? 0.05 : 0.15) << enc;
    EXPECT_LT(pose_math::RotationErrorRad(est, truth) * 180.0 / M_PI, 2.0) << enc;
    std::printf("%s: %s, chi2 %.1f (gate %.1f)\n", enc.c_str(), ToString(r.status), r.cone_pose.chi2,
                r.cone_pose.chi2_threshold);
  }
}

TEST_F(Adapter, PoseMessageCarriesTheInvertedCovariance) {
  const FrameResult r = adapter_.Process(Frame("rgb8", 5.0), std::nullopt);
  ASSERT_EQ(r.status, FrameStatus::kPose) << r.message;
  EXPECT_EQ(r.pose->header.frame_id, "cones");
  EXPECT_DOUBLE_EQ(r.pose->header.stamp.toSec(), 5.0);
  // The same pose and covariance by hand: invert the solver's T_camera_cones with its 7x7, then convert.
  const pose_math::PoseWithCovariance inv =
      pose_math::Invert(pose_math::PoseWithCovariance{r.cone_pose.pnp.T_camera_model, r.cone_pose.pnp.cov7});
  const pose_math::Matrix6d cov6 = pose_math::CovarianceRosFromThesis(inv.pose.q, inv.cov);
  for (int i = 0; i < 36; ++i) EXPECT_NEAR(r.pose->pose.covariance[size_t(i)], cov6(i / 6, i % 6), 1e-15);
  EXPECT_NEAR(r.pose->pose.pose.position.x, inv.pose.t.x(), 1e-12);
  // Position standard deviations of a few cm at 3.5 m with sigma_px = 1 at 512x384.
  for (int i = 0; i < 3; ++i) {
    EXPECT_GT(cov6(i, i), 1e-6);
    EXPECT_LT(cov6(i, i), 0.01);
  }
}

TEST_F(Adapter, CameraInfoValidation) {
  std::string error;
  sensor_msgs::CameraInfo info = CameraInfo(kCamera);
  info.D[1] = INFINITY;
  EXPECT_FALSE(adapter_.SetCameraInfo(info, &error));
  EXPECT_NE(error.find("NaN or inf"), std::string::npos) << error;
  FrameResult r = adapter_.Process(Frame("rgb8", 1.0), std::nullopt);
  EXPECT_EQ(r.status, FrameStatus::kBadCameraInfo);
  EXPECT_FALSE(r.pose);

  info = CameraInfo(kCamera);
  info.K[0] = 0.0;
  EXPECT_FALSE(adapter_.SetCameraInfo(info, &error));
  EXPECT_NE(error.find("uncalibrated"), std::string::npos) << error;
  info = CameraInfo(kCamera);
  info.distortion_model = "equidistant";
  EXPECT_FALSE(adapter_.SetCameraInfo(info, &error));
  EXPECT_NE(error.find("equidistant"), std::string::npos) << error;

  info = CameraInfo(kCamera);
  info.width = 1024, info.height = 768;  // a binned camera_info with the full-size K: refuse, don't guess
  EXPECT_TRUE(adapter_.SetCameraInfo(info, &error));
  r = adapter_.Process(Frame("rgb8", 2.0), std::nullopt);
  EXPECT_EQ(r.status, FrameStatus::kSizeMismatch);
  EXPECT_NE(r.message.find("512x384 but camera_info is 1024x768"), std::string::npos) << r.message;

  EXPECT_TRUE(adapter_.SetCameraInfo(CameraInfo(kCamera), &error));
  EXPECT_EQ(adapter_.Process(Frame("rgb8", 3.0), std::nullopt).status, FrameStatus::kPose);
  EXPECT_EQ(adapter_.counters().bad_camera_info_msgs, 3u);
  EXPECT_EQ(adapter_.counters().size_mismatch, 1u);
}

TEST(AdapterNoInfo, FramesBeforeCameraInfo) {
  TrackerAdapter adapter(Config(NAN), Layout());
  const FrameResult r = adapter.Process(Frame("rgb8", 1.0), std::nullopt);
  EXPECT_EQ(r.status, FrameStatus::kNoCameraInfo);
  EXPECT_FALSE(r.pose);
  EXPECT_FALSE(r.detections);
}

TEST_F(Adapter, ShortDataAndStepAreBadImages) {
  auto img = Frame("rgb8", 1.0);
  img->data.resize(img->data.size() / 2);
  FrameResult r = adapter_.Process(img, std::nullopt);
  EXPECT_EQ(r.status, FrameStatus::kBadImage);
  EXPECT_NE(r.message.find("bytes"), std::string::npos);
  img = Frame("rgb8", 2.0);
  img->step = img->width;  // one byte per pixel for rgb8
  r = adapter_.Process(img, std::nullopt);
  EXPECT_EQ(r.status, FrameStatus::kBadImage);
  EXPECT_NE(r.message.find("step"), std::string::npos);
  EXPECT_EQ(adapter_.counters().bad_image, 2u);
}

TEST_F(Adapter, LastPosePredictsAndTimeGoingBackClearsIt) {
  EXPECT_EQ(adapter_.Process(Frame("rgb8", 10.0), std::nullopt).prediction_source, "none");
  FrameResult r = adapter_.Process(Frame("rgb8", 10.033), std::nullopt);
  EXPECT_EQ(r.prediction_source, "last_pose");
  EXPECT_TRUE(r.detections->motion_checked);
  EXPECT_FALSE(r.time_jumped_back);
  r = adapter_.Process(Frame("rgb8", 11.0), std::nullopt);  // older than prediction_max_age_s
  EXPECT_EQ(r.prediction_source, "none");
  r = adapter_.Process(Frame("rgb8", 5.0), std::nullopt);  // a bag loop
  EXPECT_TRUE(r.time_jumped_back);
  EXPECT_EQ(r.prediction_source, "none");
  EXPECT_EQ(adapter_.counters().time_jumps, 1u);
  EXPECT_EQ(r.status, FrameStatus::kPose);
}

// After an outage pose_ekf's coasting estimate can be far off: its tf
// prediction then matches no cone. Once no pose was accepted for
// reacquire_after_s the tracker re-initialises without it.
TEST_F(Adapter, ReacquiresWhenTheTfPredictionKeepsFailing) {
  ASSERT_EQ(adapter_.Process(Frame("rgb8", 10.0), std::nullopt).status, FrameStatus::kPose);
  pose_math::Pose drifted = Truth();
  drifted.t += Eigen::Vector3d(1.5, -1.0, 0.5);  // metres of drift
  FrameResult r = adapter_.Process(Frame("rgb8", 10.5), drifted);
  EXPECT_EQ(r.prediction_source, "tf");
  EXPECT_NE(r.status, FrameStatus::kPose);
  r = adapter_.Process(Frame("rgb8", 10.5 + adapter_.config().reacquire_after_s + 0.1), drifted);
  EXPECT_EQ(r.prediction_source, "reacquire");
  ASSERT_EQ(r.status, FrameStatus::kPose) << r.message;
  const auto& p = r.pose->pose.pose.position;
  EXPECT_LT((Eigen::Vector3d(p.x, p.y, p.z) - Truth().t).norm(), 0.1);
  EXPECT_EQ(adapter_.counters().reacquisitions, 1u);
  r = adapter_.Process(Frame("rgb8", 11.7), Truth());  // tracking again: tf predicts
  EXPECT_EQ(r.prediction_source, "tf");
  EXPECT_EQ(r.status, FrameStatus::kPose) << r.message;
}

// pose_ekf back from an outage metres off and sure of it (rig_sim look_away seed 42): the re-acquired pose predicts
// the next frames while tf contradicts it, so their cones keep their own ids; once tf agrees again, tf predicts. The
// sequence on one layout file (RIG_MODEL_LAYOUTS_DIR).
// Whether every observed cone's mid and base lie in the message's orange regions (within 1 px; not the peak, which
// the line search puts on the edges' apex, where the tip is narrower than a pixel and not orange).
bool ConesInOrange(const ConeObservations& msg) {
  for (const ConeObservation& o : msg.cones)
    for (const auto& p : {o.mid_px, o.base_px}) {
      bool in = false;
      for (const sensor_msgs::RegionOfInterest& roi : msg.orange) {
        const rig_model::ImageBox b = rig_model::FromRoi(roi);
        in = in || (roi.do_rectify && p[0] > b.u_min - 1.0 && p[0] < b.u_max + 1.0 && p[1] > b.v_min - 1.0 &&
                    p[1] < b.v_max + 1.0);
      }
      if (!in) return false;
    }
  return true;
}

void ExpectOwnTrackOverrulesContradictingTf(const std::string& file) {
  SCOPED_TRACE(file);
  const std::string path = RIG_MODEL_LAYOUTS_DIR "/" + file;
  NodeConfig config;
  config.layout_file = path;
  std::vector<ConeModel> layout;
  std::string error;
  ASSERT_TRUE(LoadLayoutFile(path, &layout, &error)) << error;
  TrackerAdapter adapter(config, layout);
  ASSERT_TRUE(adapter.SetCameraInfo(CameraInfo(kCamera), &error)) << error;
  const rig_sim::Scene scene = rig_model::LoadLayoutFile(path);
  const auto frame = [&](double stamp_s) { return Frame("rgb8", stamp_s, scene); };
  ASSERT_EQ(adapter.Process(frame(10.0), std::nullopt).status, FrameStatus::kPose);
  pose_math::Pose drifted = Truth();
  drifted.t += Eigen::Vector3d(1.5, -1.0, 0.5);
  EXPECT_NE(adapter.Process(frame(10.5), drifted).status, FrameStatus::kPose);
  FrameResult r = adapter.Process(frame(10.5 + adapter.config().reacquire_after_s + 0.1), drifted);
  ASSERT_EQ(r.prediction_source, "reacquire");
  ASSERT_EQ(r.status, FrameStatus::kPose) << r.message;

  for (const double stamp_s : {11.7, 11.8}) {  // pose_ekf still off: the own track predicts
    r = adapter.Process(frame(stamp_s), drifted);
    EXPECT_EQ(r.prediction_source, "last_pose");
    ASSERT_EQ(r.status, FrameStatus::kPose) << r.message;
    ASSERT_TRUE(r.observations);
    EXPECT_EQ(r.observations->cones.size(), 3u);
    EXPECT_TRUE(ConesInOrange(*r.observations));
  }
  EXPECT_EQ(adapter.counters().tf_overruled, 2u);
  r = adapter.Process(frame(11.9), Truth());  // pose_ekf re-initialised from those poses: tf agrees
  EXPECT_EQ(r.prediction_source, "tf");
  EXPECT_EQ(r.status, FrameStatus::kPose) << r.message;
  r = adapter.Process(frame(12.0), drifted);  // the own track has ended: tf predicts even when off
  EXPECT_EQ(r.prediction_source, "tf");
  EXPECT_NE(r.status, FrameStatus::kPose);
  EXPECT_EQ(adapter.counters().tf_overruled, 2u);
}

TEST(AdapterOwnTrack, AReacquiredTrackOverrulesATfThatContradictsIt) {
  ExpectOwnTrackOverrulesContradictingTf("asymmetric.yaml");
  ExpectOwnTrackOverrulesContradictingTf("default.yaml");  // three identical cones: the tie-break is tf's bearing
}

TEST_F(Adapter, ReconfigureRebuildsTheColourTableAndRefusesBadValues) {
  SegmenterConfig seg = adapter_.config().segmenter;
  seg.hsi.hue_min_deg = 200.0, seg.hsi.hue_max_deg = 252.0;  // blue
  adapter_.Reconfigure(seg, adapter_.config().pose, adapter_.config().debug);
  FrameResult r = adapter_.Process(Frame("rgb8", 1.0), std::nullopt);
  EXPECT_EQ(r.status, FrameStatus::kNoCones) << r.message;

  SegmenterConfig bad = seg;
  bad.hsi.sat_min = 0.9, bad.hsi.sat_max = 0.1;
  EXPECT_THROW(adapter_.Reconfigure(bad, adapter_.config().pose, adapter_.config().debug), std::invalid_argument);
  EXPECT_DOUBLE_EQ(adapter_.config().segmenter.hsi.sat_min, seg.hsi.sat_min);  // unchanged
  ConePoseConfig bad_pose = adapter_.config().pose;
  bad_pose.chi2_probability = 1.5;
  EXPECT_THROW(adapter_.Reconfigure(seg, bad_pose, adapter_.config().debug), std::invalid_argument);

  adapter_.Reconfigure(SegmenterConfig(), adapter_.config().pose, adapter_.config().debug);
  r = adapter_.Process(Frame("rgb8", 2.0), std::nullopt);
  EXPECT_EQ(r.status, FrameStatus::kPose) << r.message;
}

TEST(AdapterHeading, PriorPicksAmongTheSymmetricPoses) {
  // The camera stands at a bearing of 10 deg; a prior 120 deg off picks the rotated pose, the right
  // one picks the truth.
  const double truth_deg = std::atan2(kEye.y(), kEye.x()) * 180.0 / M_PI;
  for (const double offset_deg : {0.0, 120.0, -120.0}) {
    TrackerAdapter adapter(Config(truth_deg + offset_deg), Layout());
    std::string error;
    ASSERT_TRUE(adapter.SetCameraInfo(CameraInfo(kCamera), &error));
    const FrameResult r = adapter.Process(Frame("rgb8", 1.0), std::nullopt);
    ASSERT_EQ(r.status, FrameStatus::kPose) << r.message;
    const auto& p = r.pose->pose.pose.position;
    const double bearing_deg = std::atan2(p.y, p.x) * 180.0 / M_PI;
    EXPECT_NEAR(std::remainder(bearing_deg - truth_deg - offset_deg, 360.0), 0.0, 3.0) << offset_deg;
  }
}

}  // namespace
// The two-cone start through the adapter: two cones in view, no prediction; gravity from the caller.
TEST(AdapterTwoCones, TwoConesAndGravityStartTheTrackWithoutAPrediction) {
  rig_sim::Scene scene;
  std::string error;
  ASSERT_TRUE(
      rig_sim::ParseSceneYaml("cones:\n  - {x_m: 0.0, y_m: 0.0, height_m: 0.71, style: plain}\n"
                              "  - {x_m: 1.5, y_m: 0.0, height_m: 0.71, style: plain}\n"
                              "  - {x_m: 5.0, y_m: 3.0, height_m: 0.46, style: plain}\n",
                              &scene, &error))
      << error;
  std::vector<ConeModel> layout;
  for (const auto& c : scene.cones) layout.push_back({c.base_m, c.height_m, c.tau});
  const rig_sim::TruePose truth = LookAt(Eigen::Vector3d(0.75, 4.0, 1.4), Eigen::Vector3d(0.75, 0.0, 0.35));
  const Eigen::Vector3d up = truth.R_cones_camera.transpose().col(2);  // the layout's z in the camera
  NodeConfig config;
  config.layout_file = "two_cones.yaml";  // the adapter takes the layout as given
  const auto make = [&](double sigma_deg) {
    config.two_cone_gravity_sigma_deg = sigma_deg;
    auto a = std::make_unique<TrackerAdapter>(config, layout);
    std::string e;
    EXPECT_TRUE(a->SetCameraInfo(CameraInfo(kCamera), &e)) << e;
    return a;
  };
  auto adapter = make(3.0);
  const FrameResult no_gravity = adapter->Process(Frame("rgb8", 1.0, scene, truth), std::nullopt);
  EXPECT_EQ(no_gravity.status, FrameStatus::kTooFewCones) << no_gravity.message;
  EXPECT_EQ(adapter->counters().two_cone_no_gravity, 1u);
  const FrameResult r = adapter->Process(Frame("rgb8", 1.1, scene, truth), std::nullopt, std::nullopt, up);
  ASSERT_EQ(r.status, FrameStatus::kPose) << r.message;
  EXPECT_EQ(r.prediction_source, "two_cones_gravity");
  ASSERT_TRUE(r.pose);
  EXPECT_LT((rig_model::FromPoseMsg(r.pose->pose.pose).t - truth.p_camera_in_cones_m).norm(), 0.14);
  ASSERT_TRUE(r.observations);
  EXPECT_EQ(r.observations->cones.size(), 2u);  // pose_ekf gets both cones with their ids
  EXPECT_EQ(adapter->counters().two_cone_poses, 1u);
  EXPECT_EQ(r.detections->prediction_source, "two_cones_gravity");
  EXPECT_EQ(r.detections->chi2_dof, 8);
  // Off: three cones needed, gravity or not.
  auto off = make(0.0);
  const FrameResult r_off = off->Process(Frame("rgb8", 1.0, scene, truth), std::nullopt, std::nullopt, up);
  EXPECT_EQ(r_off.status, FrameStatus::kTooFewCones);
  EXPECT_EQ(off->counters().two_cone_poses + off->counters().two_cone_no_gravity, 0u);
}

}  // namespace cone_tracker
