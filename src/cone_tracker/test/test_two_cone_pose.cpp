// The two-cone start (two_cone_pose.h) on rendered rig_sim frames, and the gravity window.
#include <gtest/gtest.h>

#include <cmath>

#include <boost/math/distributions/chi_squared.hpp>

#include "cone_tracker/testing/vision_frames.h"
#include "cone_tracker/vision/two_cone_pose.h"
#include "pose_math/covariance.h"
#include "pose_math/quaternion.h"
#include "pose_math/rotation.h"

namespace cone_tracker {
namespace {

// Two cones 1.5 m apart in front of the camera and a third, shorter, out of view: far to the camera's side
// (`telling`: the mirror pose, the camera at y = -4, would see it) or far along the pair's line (neither pose
// sees it, so nothing tells which side of the pair the camera is on).
rig_sim::Scene PairScene(bool telling) {
  rig_sim::Scene s;
  std::string error;
  std::string yaml =
      "cones:\n  - {x_m: 0.0, y_m: 0.0, height_m: 0.71, style: plain}\n"
      "  - {x_m: 1.5, y_m: 0.0, height_m: 0.71, style: plain}\n";
  yaml += telling ? "  - {x_m: 5.0, y_m: 3.0, height_m: 0.46, style: plain}\n"
                  : "  - {x_m: 12.0, y_m: 0.0, height_m: 0.46, style: plain}\n";
  EXPECT_TRUE(rig_sim::ParseSceneYaml(yaml, &s, &error)) << error;
  return s;
}

const Eigen::Vector3d kEye(0.75, 4.0, 1.4), kTarget(0.75, 0.0, 0.35);

struct Frame {
  SegmentationResult seg;
  std::vector<ConeModel> models;
  pose_math::Pose truth;  // T_camera_cones
  CameraModel camera;
};

Frame Render(const rig_sim::Scene& scene) {
  Frame f;
  const SimFrame sim = RenderSim(scene, LookAt(kEye, kTarget));
  Segmenter seg{SegmenterConfig()};
  f.seg = seg.Process({sim.rgb.data(), sim.camera.width_px, sim.camera.height_px, sim.camera.width_px * 3, "rgb8"},
                      sim.camera);
  for (const auto& c : scene.cones) f.models.push_back({c.base_m, c.height_m, c.tau});
  const Eigen::Matrix3d R = sim.pose.R_cones_camera.transpose();
  f.truth.q = pose_math::QuatFromRotation(R);
  f.truth.t = -R * sim.pose.p_camera_in_cones_m;
  f.camera = sim.camera;
  return f;
}

// The layout's up in the camera, turned by angle_deg about the camera's x axis.
Eigen::Vector3d UpTurned(const pose_math::Pose& T_camera_cones, double angle_deg) {
  return pose_math::RotX(angle_deg * M_PI / 180.0) * pose_math::RotationFromQuat(T_camera_cones.q).col(2);
}

// The solution's error against the truth (ROS order: position, then a left rotation), and its Mahalanobis
// distance under the published covariance.
double Mahalanobis(const PnpResult& r, const pose_math::Pose& truth) {
  Eigen::Matrix<double, 6, 1> e;
  e.head<3>() = truth.t - r.T_camera_model.t;
  e.tail<3>() = pose_math::RotationVectorFromQuat(pose_math::QuatFromRotation(
      pose_math::RotationFromQuat(truth.q) * pose_math::RotationFromQuat(r.T_camera_model.q).transpose()));
  return e.dot(r.cov6_ros.ldlt().solve(e));
}

TEST(TwoConePose, TwoRenderedConesAndGravityGiveThePoseWithinItsCovariance) {
  const Frame f = Render(PairScene(true));
  ASSERT_EQ(f.seg.cones.size(), 2u) << "the scene must show exactly two cones";
  const ConePoseConfig cfg;
  // Gravity 2 degrees off, its stated sigma 3 (two_cone_gravity_sigma_deg's default).
  const ConePoseResult r = EstimateTwoConePose(f.seg.cones, f.seg.rejected, f.models, f.camera, cfg,
                                               GravityPrior{UpTurned(f.truth, 2.0), 3.0 * M_PI / 180.0});
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.cone_of_detection, (std::vector<int>{1, 0}));  // detections by u: seen from y = 4, cone 1 is left
  EXPECT_EQ(r.chi2_dof, 8);
  EXPECT_LE(r.chi2, r.chi2_threshold);
  // The covariance covers the error: inside the 99.9 % ellipsoid of six dof.
  const double limit = boost::math::quantile(boost::math::chi_squared(6), 0.999);
  EXPECT_LT(Mahalanobis(r.pnp, f.truth), limit);
  const Eigen::Matrix3d R = pose_math::RotationFromQuat(r.pnp.T_camera_model.q);
  const Eigen::Vector3d eye = -R.transpose() * r.pnp.T_camera_model.t;
  // A 2-degree tilt error at 4 m moves the eye by about 0.14 m; the image pulls most of it back.
  EXPECT_LT((eye - kEye).norm(), 0.14);
  // The mirror hypothesis (cone 1 left, the camera on the other side) would put the third cone in plain view.
}

TEST(TwoConePose, GravityFarOutsideItsSigmaIsRefused) {
  const Frame f = Render(PairScene(true));
  ASSERT_EQ(f.seg.cones.size(), 2u);
  const ConePoseResult r = EstimateTwoConePose(f.seg.cones, f.seg.rejected, f.models, f.camera, ConePoseConfig(),
                                               GravityPrior{UpTurned(f.truth, 25.0), 2.0 * M_PI / 180.0});
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(r.rejected_by & kPoseChi2) << r.error;
}

TEST(TwoConePose, TwoIdenticalConesAreAmbiguousUntilTheHeadingPriorDecides) {
  const Frame f = Render(PairScene(false));
  ASSERT_EQ(f.seg.cones.size(), 2u);
  ConePoseConfig cfg;
  const GravityPrior g{UpTurned(f.truth, 0.0), 3.0 * M_PI / 180.0};
  const ConePoseResult ambiguous = EstimateTwoConePose(f.seg.cones, f.seg.rejected, f.models, f.camera, cfg, g);
  EXPECT_FALSE(ambiguous.ok);
  EXPECT_TRUE(ambiguous.rejected_by & kPoseAmbiguous) << ambiguous.error;
  cfg.initial_heading_rad = std::atan2(kEye.y(), kEye.x());
  const ConePoseResult picked = EstimateTwoConePose(f.seg.cones, f.seg.rejected, f.models, f.camera, cfg, g);
  ASSERT_TRUE(picked.ok) << picked.error;
  EXPECT_EQ(picked.cone_of_detection, (std::vector<int>{1, 0}));
}

TEST(TwoConePose, OneConeALargeLayoutOrNoGravityAreRefused) {
  const Frame f = Render(PairScene(true));
  ASSERT_EQ(f.seg.cones.size(), 2u);
  const GravityPrior g{UpTurned(f.truth, 0.0), 0.05};
  const std::vector<ConeDetection> one(f.seg.cones.begin(), f.seg.cones.begin() + 1);
  const ConePoseResult r = EstimateTwoConePose(one, {}, f.models, f.camera, ConePoseConfig(), g);
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(r.rejected_by & kPoseTooFewCones);
  std::vector<ConeModel> large = f.models;  // beyond kTwoConeMaxLayout: n (n - 1) pairings are too many
  while (large.size() <= kTwoConeMaxLayout) large.push_back({Eigen::Vector3d(20.0 + double(large.size()), -9.0, 0.0)});
  const ConePoseResult r_large = EstimateTwoConePose(f.seg.cones, {}, large, f.camera, ConePoseConfig(), g);
  EXPECT_FALSE(r_large.ok);
  EXPECT_TRUE(r_large.rejected_by & kPoseTooFewCones) << r_large.error;
  const ConePoseResult nan = EstimateTwoConePose(f.seg.cones, {}, f.models, f.camera, ConePoseConfig(),
                                                 GravityPrior{Eigen::Vector3d::Constant(NAN), 0.05});
  EXPECT_FALSE(nan.ok);
  EXPECT_EQ(nan.error, "the two-cone start has no usable gravity");
}

TEST(GravityWindow, MeanDirectionAroundTheStampAndRefusals) {
  GravityWindow w(1.0);
  EXPECT_FALSE(w.UpAt(10.0, 0.05));  // empty
  const Eigen::Vector3d up = Eigen::Vector3d(0.0, -1.0, 0.2).normalized();
  for (int i = 0; i < 100; ++i) {
    const double t = 9.5 + 0.01 * i;
    // +-0.5 m/s^2 across up, alternating: the mean over the window cancels it.
    const Eigen::Vector3d across = (i % 2 ? 0.5 : -0.5) * up.unitOrthogonal();
    ASSERT_TRUE(w.Add(t, 9.81 * up + across));
  }
  const auto got = w.UpAt(10.0, 0.05);
  ASSERT_TRUE(got);
  // Eleven samples in the window: one unpaired 0.5 m/s^2 is 0.5 / 11 / 9.81 = 0.0046 rad.
  EXPECT_LT(std::acos(std::min(1.0, got->dot(up))), 0.006);
  EXPECT_FALSE(w.UpAt(12.0, 0.05)) << "no sample near the stamp";
  EXPECT_FALSE(w.Add(10.5, Eigen::Vector3d(NAN, 0, 9.8)));
  GravityWindow free_fall;
  free_fall.Add(1.0, Eigen::Vector3d(0, 0, 2.0));
  EXPECT_FALSE(free_fall.UpAt(1.0, 0.05)) << "a mean far from g is no gravity";
  w.Add(3.0, 9.81 * up);  // time jumped back: the older samples go
  EXPECT_FALSE(w.UpAt(10.0, 0.05));
  EXPECT_TRUE(w.UpAt(3.0, 0.05));
}

}  // namespace
}  // namespace cone_tracker
