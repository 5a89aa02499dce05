// Detections of rig_sim frames to poses, against the rendering pose.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "cone_tracker/pose/algorithms.h"
#include "cone_tracker/testing/vision_frames.h"
#include "cone_tracker/vision/cone_pose.h"
#include "pose_math/rotation.h"

namespace cone_tracker {
namespace {

std::vector<ConeModel> Models(const rig_sim::Scene& scene) {
  std::vector<ConeModel> m;
  for (const auto& c : scene.cones) m.push_back({c.base_m, c.height_m, c.tau});
  return m;
}

pose_math::Pose TruthCameraCones(const rig_sim::TruePose& p) {
  const Eigen::Matrix3d R = p.R_cones_camera.transpose();
  return PoseFromRt(R, -R * p.p_camera_in_cones_m);
}

struct Case {
  SimFrame frame;
  SegmentationResult seg;
  std::vector<ConeModel> models;
  pose_math::Pose truth;
};

Case Make(const rig_sim::Scene& scene, const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  Case c;
  c.frame = RenderSim(scene, LookAt(eye, target));
  Segmenter seg{SegmenterConfig()};
  const SimFrame& f = c.frame;
  c.seg = seg.Process({f.rgb.data(), f.camera.width_px, f.camera.height_px, f.camera.width_px * 3, "rgb8"}, f.camera);
  c.models = Models(scene);
  c.truth = TruthCameraCones(f.pose);
  return c;
}

// Three plain cones, two of one height: no rotational symmetry.
rig_sim::Scene AsymmetricScene() {
  rig_sim::Scene s;
  std::string error;
  EXPECT_TRUE(
      rig_sim::ParseSceneYaml("cones:\n  - {x_m: 1.0, y_m: 0.0, height_m: 0.71, style: plain}\n"
                              "  - {x_m: -0.45, y_m: 0.8, height_m: 0.46, style: plain}\n"
                              "  - {x_m: -0.55, y_m: -0.8, height_m: 0.71, style: plain}\n",
                              &s, &error))
      << error;
  return s;
}

double PositionErrorM(const pose_math::Pose& a, const pose_math::Pose& b) {
  auto eye = [](const pose_math::Pose& T) {
    return Eigen::Vector3d(-(pose_math::RotationFromQuat(T.q).transpose() * T.t));
  };
  return (eye(a) - eye(b)).norm();
}

}  // namespace

TEST(ConePose, CorrectedModelPointsFaceTheCamera) {
  const ConeModel cone{Eigen::Vector3d(1, 0, 0), 0.7, 1.0 / 7.0};
  const auto p = CorrectedModelPoints(cone, Eigen::Vector3d(5, 0, 1.5));
  EXPECT_TRUE(p[0].isApprox(Eigen::Vector3d(1, 0, 0.7)));
  EXPECT_TRUE(p[1].isApprox(Eigen::Vector3d(1.05, 0, 0.35)));
  EXPECT_TRUE(p[2].isApprox(Eigen::Vector3d(1.1, 0, 0)));
}

TEST(ConePose, SymmetryOfTheEquilateralLayoutIsDetected) {
  EXPECT_TRUE(LayoutHasRotationalSymmetry(Models(rig_sim::DefaultScene())));
  EXPECT_FALSE(LayoutHasRotationalSymmetry(Models(AsymmetricScene())));
}

TEST(ConePose, WithPredictionMatchesAndRecoversThePose) {
  const Case c = Make(rig_sim::DefaultScene(), Eigen::Vector3d(0.54, 3.15, 1.5), Eigen::Vector3d(0, 0, 0.3));
  ASSERT_EQ(c.seg.cones.size(), 3u);
  pose_math::Pose pred = c.truth;
  pred.t += Eigen::Vector3d(0.05, -0.03, 0.08);
  const ConePoseResult r = EstimateConePose(c.seg.cones, c.models, c.frame.camera, ConePoseConfig(), pred);
  ASSERT_TRUE(r.ok) << r.error << " chi2 " << r.chi2 << " > " << r.chi2_threshold;
  const double dp = PositionErrorM(r.pnp.T_camera_model, c.truth);
  const double dr = pose_math::RotationErrorRad(r.pnp.T_camera_model, c.truth) * 180.0 / M_PI;
  std::printf("default layout at 3.2 m: position error %.3f m, rotation error %.2f deg, chi2 %.1f (gate %.1f)\n", dp,
              dr, r.chi2, r.chi2_threshold);
  EXPECT_LT(dp, 0.05);
  EXPECT_LT(dr, 1.0);
  // A prediction a metre off fails the relative-motion gate (6.4.2) or the assignment.
  pose_math::Pose far = c.truth;
  far.t += Eigen::Vector3d(0.0, 0.0, 1.0);
  ConePoseConfig tight;
  tight.max_assignment_px = 400.0;
  EXPECT_FALSE(EstimateConePose(c.seg.cones, c.models, c.frame.camera, tight, far).ok);
}

TEST(ConePose, WithoutPredictionAsymmetricLayoutAndGates) {
  const rig_sim::Scene s = AsymmetricScene();
  const Case c = Make(s, Eigen::Vector3d(0.54, 3.15, 1.5), Eigen::Vector3d(0, 0, 0.3));
  ASSERT_EQ(c.seg.cones.size(), 3u);
  const CameraModel cam = c.frame.camera;
  const ConePoseResult r = EstimateConePose(c.seg.cones, c.models, cam, ConePoseConfig(), std::nullopt);
  ASSERT_TRUE(r.ok) << r.error << " chi2 " << r.chi2 << " > " << r.chi2_threshold;
  const double dp = PositionErrorM(r.pnp.T_camera_model, c.truth);
  std::printf("asymmetric layout, no prediction: position error %.3f m\n", dp);
  EXPECT_LT(dp, 0.05);
  // A detection moved 25 px sideways fails the residual gate (6.4.1).
  std::vector<ConeDetection> moved = c.seg.cones;
  moved[0].peak_undist_px.x() += 25.0, moved[0].mid_undist_px.x() += 25.0, moved[0].base_undist_px.x() += 25.0;
  const ConePoseResult bad = EstimateConePose(moved, c.models, cam, ConePoseConfig(), r.pnp.T_camera_model);
  EXPECT_FALSE(bad.ok);
  // Two cones: no pose.
  const std::vector<ConeDetection> two(c.seg.cones.begin(), c.seg.cones.begin() + 2);
  EXPECT_EQ(EstimateConePose(two, c.models, cam, ConePoseConfig(), std::nullopt).rejected_by, kPoseTooFewCones);
}

TEST(ConePose, SymmetricLayoutResolvedByTheHeadingPrior) {
  const rig_sim::Scene scene = rig_sim::EquilateralScene(1.5, 0.71, rig_sim::ConeStyle::kPlain);
  const Eigen::Vector3d eye(0.54, 3.15, 1.5);
  const Case c = Make(scene, eye, Eigen::Vector3d(0, 0, 0.3));
  ASSERT_EQ(c.seg.cones.size(), 3u);
  ConePoseConfig cfg;
  cfg.initial_heading_rad = std::atan2(eye.y(), eye.x()) + 0.3;  // roughly right
  const ConePoseResult r = EstimateConePose(c.seg.cones, c.models, c.frame.camera, cfg, std::nullopt);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_LT(PositionErrorM(r.pnp.T_camera_model, c.truth), 0.05);
  // The prior 120 degrees off picks the rotated, equally good pose: the ambiguity is real.
  cfg.initial_heading_rad += 2.0 * M_PI / 3.0;
  const ConePoseResult rotated = EstimateConePose(c.seg.cones, c.models, c.frame.camera, cfg, std::nullopt);
  ASSERT_TRUE(rotated.ok);
  EXPECT_GT(PositionErrorM(rotated.pnp.T_camera_model, c.truth), 1.0);
  EXPECT_NEAR(rotated.pnp.reproj_rms_px, r.pnp.reproj_rms_px, 0.05);
}

// The detectors give the image midpoint of peak and base as the mid point; the
// model's mid is the 3-D midpoint, which perspective moves towards the farther
// end. With exact peaks and bases, seen steeply from above and close, the pose
// must come out exact: the solver uses the image of the 3-D midpoint.
TEST(ConePose, ImageMidpointOfPeakAndBaseGivesAnUnbiasedPose) {
  const rig_sim::Scene s = AsymmetricScene();
  const std::vector<ConeModel> models = Models(s);
  const rig_sim::TruePose view = LookAt(Eigen::Vector3d(0.3, 2.2, 2.0), Eigen::Vector3d(0, 0, 0));
  const pose_math::Pose truth = TruthCameraCones(view);
  CameraModel cam;
  cam.width_px = 1024, cam.height_px = 768, cam.fx_px = cam.fy_px = 770, cam.cx_px = 512, cam.cy_px = 384;
  const Eigen::Matrix3d R = pose_math::RotationFromQuat(truth.q);
  auto project = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d c = R * p + truth.t;
    return Eigen::Vector2d(cam.fx_px * c.x() / c.z() + cam.cx_px, cam.fy_px * c.y() / c.z() + cam.cy_px);
  };
  std::vector<ConeDetection> dets;
  double worst_mid_bias_px = 0.0;
  for (const ConeModel& m : models) {
    const auto pts = CorrectedModelPoints(m, view.p_camera_in_cones_m);
    ConeDetection d;
    d.peak_undist_px = project(pts[0]), d.base_undist_px = project(pts[2]);
    d.mid_undist_px = 0.5 * (d.peak_undist_px + d.base_undist_px);  // as the segmenter gives it
    worst_mid_bias_px = std::max(worst_mid_bias_px, (d.mid_undist_px - project(pts[1])).norm());
    dets.push_back(d);
  }
  ASSERT_GT(worst_mid_bias_px, 3.0) << "the view must make the image midpoint a biased mid point";
  for (const bool predicted : {false, true}) {
    pose_math::Pose pred = truth;
    pred.t += Eigen::Vector3d(0.04, -0.03, 0.05);
    const ConePoseResult r =
        EstimateConePose(dets, models, cam, ConePoseConfig(), predicted ? std::optional(pred) : std::nullopt);
    ASSERT_TRUE(r.ok) << r.error;
    const double dp = PositionErrorM(r.pnp.T_camera_model, truth);
    const double dr = pose_math::RotationErrorRad(r.pnp.T_camera_model, truth) * 180.0 / M_PI;
    std::printf(
        "exact peaks and bases, image midpoints %.1f px off (prediction %d): position error %.2f mm, "
        "rotation %.4f deg, reprojection RMS %.3f px\n",
        worst_mid_bias_px, int(predicted), 1e3 * dp, dr, r.pnp.reproj_rms_px);
    EXPECT_LT(dp, 1e-4);
    EXPECT_LT(dr, 0.005);
  }
}

}  // namespace cone_tracker
