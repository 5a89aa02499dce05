// Association of 1, 2, 3 cones through a predicted pose (pose/associate.h),
// its agreement with 3.1.6's correspondence, and the point covariances.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstdio>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "cone_tracker/pose/associate.h"
#include "cone_tracker/vision/cone_pose.h"
#include "cone_tracker/vision/segmenter.h"
#include "pose_math/rotation.h"

namespace cone_tracker {
namespace {

// rig_model's asymmetric.yaml: a short third cone and uneven spacing.
std::vector<ConeModel> Asymmetric() {
  std::vector<ConeModel> l(3);
  l[0].base_m = {1.00, 0.00, 0}, l[1].base_m = {-0.40, 0.85, 0}, l[2].base_m = {-0.60, -0.85, 0};
  l[2].height_m = 0.46;
  return l;
}

std::vector<ConeModel> Equilateral() {
  std::vector<ConeModel> l(3);
  for (int i = 0; i < 3; ++i) {
    const double a = 2.0 * M_PI * i / 3.0, r = 1.5 / std::sqrt(3.0);
    l[size_t(i)].base_m = {r * std::cos(a), r * std::sin(a), 0};
  }
  return l;
}

CameraModel Camera() {
  CameraModel c;
  c.width_px = 640, c.height_px = 480, c.fx_px = c.fy_px = 500, c.cx_px = 319.5, c.cy_px = 239.5;
  return c;
}

// The camera at `eye` (in `cones`) looking at `target`, y down: T_camera_cones.
pose_math::Pose LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R_cones_camera;
  R_cones_camera << x, y, z;
  pose_math::Pose T;
  T.q = pose_math::QuatFromRotation(R_cones_camera.transpose());
  T.t = -(R_cones_camera.transpose() * eye);
  return T;
}

const Eigen::Vector3d kEye(1.0, 4.0, 1.3), kTarget(0.0, 0.0, 0.3);

Eigen::Vector2d Project(const pose_math::Pose& T, const Eigen::Vector3d& p_cones) {
  const Eigen::Vector3d p = pose_math::Transform(T, p_cones);
  const CameraModel c = Camera();
  return {c.fx_px * p.x() / p.z() + c.cx_px, c.fy_px * p.y() / p.z() + c.cy_px};
}

// Detections of the given layout cones as the true camera at `eye` looking at `target` sees them, 0.3 px off.
std::vector<ConeDetection> Detect(const std::vector<ConeModel>& layout, const std::vector<int>& ids,
                                  const Eigen::Vector3d& eye = kEye, const Eigen::Vector3d& target = kTarget) {
  const pose_math::Pose T = LookAt(eye, target);
  std::vector<ConeDetection> out;
  int k = 0;
  for (int id : ids) {
    const auto p = CorrectedModelPoints(layout[size_t(id)], eye);
    ConeDetection d;
    const Eigen::Vector2d off(0.3 * std::cos(k), 0.3 * std::sin(k));
    ++k;
    d.peak_undist_px = d.peak_px = Project(T, p[0]) + off;
    d.mid_undist_px = d.mid_px = Project(T, p[1]) - off;
    d.base_undist_px = d.base_px = Project(T, p[2]) + off;
    const double h = (d.peak_undist_px - d.base_undist_px).norm();
    d.blob.area = 0.5 * h * h * 2.0 * layout[size_t(id)].tau;  // a triangle of base 2 tau h
    out.push_back(d);
  }
  return out;
}

// A prediction off the truth by a few centimetres and a degree (pose_ekf's).
pose_math::Pose Predicted(const Eigen::Vector3d& eye_offset = Eigen::Vector3d(0.03, -0.04, 0.02), double deg = 1.0) {
  pose_math::Pose T = LookAt(kEye + eye_offset, kTarget);
  const Eigen::Matrix3d dR = Eigen::AngleAxisd(deg * M_PI / 180.0, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  const Eigen::Vector3d eye = -(pose_math::RotationFromQuat(T.q).transpose() * T.t);
  const Eigen::Matrix3d R = dR * pose_math::RotationFromQuat(T.q);
  T.q = pose_math::QuatFromRotation(R), T.t = -(R * eye);
  return T;
}

// model: the layout's points seen from any eye (LayoutSeenFrom), unless a test gives another.
AssociationResult Associate(const std::vector<ConeDetection>& dets, const std::vector<ConeModel>& layout,
                            const pose_math::Pose& T_pred, const AssociationConfig& cfg = AssociationConfig(),
                            const ModelPointsAt& model = nullptr) {
  std::vector<ConePoints2d> pts;
  std::vector<std::array<Eigen::Matrix2d, 3>> cov;
  for (const ConeDetection& d : dets) {
    pts.push_back({d.peak_undist_px, d.mid_undist_px, d.base_undist_px});
    cov.push_back(PointCovariances(pts.back(), d.blob.area, cfg.sigma_px));
  }
  return AssociateCones(pts, cov, layout.size(), model ? model : LayoutSeenFrom(layout), Camera(), T_pred, cfg);
}

TEST(Associate, EveryLayoutConeAloneGetsItsId) {
  for (const auto& layout : {Asymmetric(), Equilateral()})
    for (int id = 0; id < 3; ++id) {
      const AssociationResult a = Associate(Detect(layout, {id}), layout, Predicted());
      ASSERT_EQ(a.cone_of_detection.size(), 1u);
      EXPECT_EQ(a.cone_of_detection[0], id);
      EXPECT_EQ(a.candidates.size(), 3u);
      EXPECT_LT(a.d2[0], 18.47);  // chi2(4) at 0.999: the peak and the base
    }
}

TEST(Associate, TwoConesInEitherOrderGetTheirIds) {
  const auto layout = Asymmetric();
  for (const std::vector<int>& ids : {std::vector<int>{0, 1}, {1, 0}, {2, 0}, {1, 2}}) {
    const AssociationResult a = Associate(Detect(layout, ids), layout, Predicted());
    EXPECT_EQ(a.cone_of_detection, ids);
    EXPECT_EQ(a.ambiguous, 0);
  }
}

// The camera swung -120 degrees around the layout: the short cone 2 is predicted
// where the tall cone 0 is seen, cone 1 where the short cone 2 is, and the tall
// cone 0 where the tall cone 1 is. Cones 0 and 2 fit no prediction (peak, mid
// and base beyond the gate); cone 1 alone would fit cone 0, but next to an
// unmatched detection sitting on a predicted base (cone 0 on cone 2's) the
// prediction is not trusted and nothing is associated.
TEST(Associate, SwappedPredictionBeyondTheGateAssociatesNothing) {
  const auto layout = Asymmetric();
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(-2.0 * M_PI / 3.0, Eigen::Vector3d::UnitZ()).matrix();
  const pose_math::Pose swapped = LookAt(Rz * kEye, kTarget);
  for (const std::vector<int>& ids : {std::vector<int>{0}, {2}, {0, 2}, {0, 1}, {1, 0}, {0, 1, 2}}) {
    const AssociationResult a = Associate(Detect(layout, ids), layout, swapped);
    EXPECT_EQ(a.candidates.size(), 3u);
    for (size_t d = 0; d < ids.size(); ++d)
      EXPECT_EQ(a.cone_of_detection[d], -1) << "cone " << ids[d] << " of " << ids.size() << " associated";
  }
  EXPECT_TRUE(Associate(Detect(layout, {0, 1}), layout, swapped).conflict);
  // The same swap on the equilateral layout cannot be told from the image:
  // identical cones at identical places. That is what a prediction is for.
  const auto eq = Equilateral();
  const AssociationResult a = Associate(Detect(eq, {0}), eq, swapped);
  EXPECT_EQ(a.cone_of_detection[0], 2);  // cone 2 predicted where cone 0 is
}

TEST(Associate, AnUncertainPredictionOfIdenticalConesIsAmbiguous) {
  const auto eq = Equilateral();
  AssociationConfig loose;
  loose.prediction_sigma_m = 3.0, loose.prediction_sigma_rad = 0.5;
  const AssociationResult a = Associate(Detect(eq, {0}), eq, Predicted(), loose);
  EXPECT_EQ(a.cone_of_detection[0], -1);
  EXPECT_EQ(a.ambiguous, 1);
  // Two cones pin the pose down much better than one.
  const AssociationResult b = Associate(Detect(Asymmetric(), {0, 2}), Asymmetric(), Predicted(), AssociationConfig());
  EXPECT_EQ(b.cone_of_detection, (std::vector<int>{0, 2}));
}

// After an outage pose_ekf's position is a metre off, with a sigma of metres, and the assignment's fit moves
// the camera that metre. (3.18)'s peak and base move with the viewpoint, so the fit takes them at every pose
// it tries: corrected once, for the predicted eye, the near short cone's points are pixels off where the
// truth puts them, and the right pair fails its gate (rig_sim look_away seed 1, 13.2-15.2 s: two cones in
// every frame, none fused, the filter 0.7-1.1 m off until a third cone came).
TEST(Associate, APredictionAMetreOffAfterAnOutageStillPairsTwoCones) {
  const auto layout = Asymmetric();
  const Eigen::Vector3d eye(0.4, -2.4, 1.3), target(0.2, -0.4, 0.3), drift(0.35, 0.8, 0.28);
  const std::vector<ConeDetection> dets = Detect(layout, {0, 2}, eye, target);
  const pose_math::Pose pred = LookAt(eye + drift, target + drift);  // the gyros keep the orientation
  AssociationConfig cfg;
  cfg.prediction_cov = Eigen::Matrix<double, 6, 6>::Zero();
  cfg.prediction_cov->diagonal() << Eigen::Vector3d::Constant(std::pow(2.0 * M_PI / 180.0, 2)),
      Eigen::Vector3d::Constant(2.0 * 2.0);
  const AssociationResult a = Associate(dets, layout, pred, cfg);
  EXPECT_EQ(a.cone_of_detection, (std::vector<int>{0, 2}));
  EXPECT_FALSE(a.conflict);
  // The points corrected for the predicted eye alone: the right pair is refused.
  const ModelPointsAt seen_from_prediction = [&](size_t c, const Eigen::Vector3d&) {
    return CorrectedModelPoints(layout[c], eye + drift);
  };
  EXPECT_NE(Associate(dets, layout, pred, cfg, seen_from_prediction).cone_of_detection, (std::vector<int>{0, 2}));
}

// The detectors set a cone's mid to the image midpoint of its peak and base. Seen from near and above, that
// is pixels from where the 3-D midpoint projects; scored, it alone would put the right cone past the gate.
TEST(Associate, ANearConeWhoseMidIsTheImageMidpointKeepsItsId) {
  const auto layout = Asymmetric();
  const Eigen::Vector3d eye(1.3, -0.9, 1.6), target = layout[0].base_m + Eigen::Vector3d(0, 0, 0.3);
  std::vector<ConeDetection> dets = Detect(layout, {0}, eye, target);
  const Eigen::Vector2d image_mid = 0.5 * (dets[0].peak_undist_px + dets[0].base_undist_px);
  const double mid_off_px = (image_mid - dets[0].mid_undist_px).norm();
  ASSERT_GT(mid_off_px * mid_off_px, 18.47) << "not a case where the mid matters";  // 1 px sigma: past chi2(4)
  dets[0].mid_undist_px = image_mid;
  const pose_math::Pose truth = LookAt(eye, target);
  const AssociationResult a = Associate(dets, layout, truth);
  EXPECT_EQ(a.cone_of_detection, (std::vector<int>{0}));
  EXPECT_LT(a.d2[0], 2.0);  // the peak and base are 0.3 px off
}

TEST(Associate, ConesBehindTheCameraOrFarOutsideAreNoCandidates) {
  const auto layout = Asymmetric();
  // Looking away from the layout: every cone is behind the camera.
  const pose_math::Pose away = LookAt(kEye, 2.0 * kEye);
  const AssociationResult a = Associate(Detect(layout, {0}), layout, away);
  EXPECT_TRUE(a.candidates.empty());
  EXPECT_EQ(a.cone_of_detection[0], -1);
  // Turned 90 degrees: the cones are far outside the image.
  const pose_math::Pose aside = LookAt(kEye, kEye + Eigen::Vector3d(4.0, -1.0, 0));
  EXPECT_TRUE(Associate(Detect(layout, {0}), layout, aside).candidates.empty());
}

// Cones predicted to overlap in the image are no candidates: a blob there is
// one merged cone or a cut one. The camera in line with cones 0 and 1.
TEST(Associate, ConesPredictedToOverlapAreLeftOut) {
  const auto layout = Asymmetric();
  const Eigen::Vector3d b0 = layout[0].base_m, b1 = layout[1].base_m;
  const Eigen::Vector3d eye = b0 + 2.5 * (b0 - b1).normalized() + Eigen::Vector3d(0, 0, 1.0);
  const pose_math::Pose T = LookAt(eye, Eigen::Vector3d(0, 0, 0.3));
  ConeDetection d;  // the near cone 0, as predicted
  const auto p = CorrectedModelPoints(layout[0], eye);
  const Eigen::Vector3d q0 = pose_math::Transform(T, p[0]), q1 = pose_math::Transform(T, p[1]),
                        q2 = pose_math::Transform(T, p[2]);
  d.peak_undist_px = Eigen::Vector2d(500 * q0.x() / q0.z() + 319.5, 500 * q0.y() / q0.z() + 239.5);
  d.mid_undist_px = Eigen::Vector2d(500 * q1.x() / q1.z() + 319.5, 500 * q1.y() / q1.z() + 239.5);
  d.base_undist_px = Eigen::Vector2d(500 * q2.x() / q2.z() + 319.5, 500 * q2.y() / q2.z() + 239.5);
  const AssociationResult a = Associate({d}, layout, T);
  EXPECT_EQ(a.overlapping, (std::vector<int>{0, 1}));
  ASSERT_EQ(a.candidates.size(), 1u);
  EXPECT_EQ(a.candidates[0].cone, 2);
  EXPECT_EQ(a.cone_of_detection[0], -1);
}

// After an outage the prediction is a metre off with a sigma to match, and may put two cones on top of each other
// that the camera sees apart. That overlap is no more than the prior's spread: both stay candidates and get their
// ids. Predicted as surely (the default prior's 5 cm and 2 degrees), the same overlap leaves both out.
TEST(Associate, AnOverlapWithinThePredictionsSpreadLeavesNoConeOut) {
  const auto layout = Asymmetric();
  const Eigen::Vector3d b0 = layout[0].base_m, b1 = layout[1].base_m, target(0, 0, 0.3);
  const Eigen::Vector3d in_line = b0 + 2.5 * (b0 - b1).normalized() + Eigen::Vector3d(0, 0, 1.0);
  const Eigen::Vector3d across = Eigen::Vector3d::UnitZ().cross(b0 - b1).normalized();
  const Eigen::Vector3d eye = in_line + 1.0 * across;  // the truth: cones 0 and 1 apart
  const std::vector<ConeDetection> dets = Detect(layout, {0, 1}, eye, target);
  // Their bases 71 px apart, each about 20 px wide.
  ASSERT_GT(std::abs(dets[0].base_undist_px.x() - dets[1].base_undist_px.x()), 60.0);
  pose_math::Pose pred = LookAt(eye, target);  // the gyros kept the orientation; the position drifted in line
  pred.t = -(pose_math::RotationFromQuat(pred.q) * in_line);
  EXPECT_EQ(Associate(dets, layout, pred).overlapping, (std::vector<int>{0, 1}));  // sure of it: left out
  AssociationConfig outage;
  outage.prediction_cov = Eigen::Matrix<double, 6, 6>::Zero();
  outage.prediction_cov->diagonal() << Eigen::Vector3d::Constant(std::pow(0.2 * M_PI / 180.0, 2)),
      Eigen::Vector3d::Constant(0.75 * 0.75);
  const AssociationResult a = Associate(dets, layout, pred, outage);
  EXPECT_TRUE(a.overlapping.empty());
  EXPECT_EQ(a.ambiguous, 0);
  EXPECT_FALSE(a.conflict);
  EXPECT_EQ(a.cone_of_detection, (std::vector<int>{0, 1}));
}

TEST(Associate, ADistractorIsLeftOut) {
  const auto layout = Asymmetric();
  std::vector<ConeDetection> dets = Detect(layout, {1, 0});
  ConeDetection far = dets[0];
  for (Eigen::Vector2d* p : {&far.peak_undist_px, &far.mid_undist_px, &far.base_undist_px})
    *p += Eigen::Vector2d(0, 150);
  dets.push_back(far);
  const AssociationResult a = Associate(dets, layout, Predicted());
  EXPECT_EQ(a.cone_of_detection, (std::vector<int>{1, 0, -1}));
}

// With three cones 3.1.6 (EstimateConePose, the pose path) decides; the
// association through the same prediction gives the same ids.
TEST(Associate, ThreeConesAgreeWithThePosePathCorrespondence) {
  for (const auto& layout : {Asymmetric(), Equilateral()}) {
    const std::vector<ConeDetection> dets = Detect(layout, {2, 0, 1});
    const pose_math::Pose pred = Predicted();
    const ConePoseResult cp = EstimateConePose(dets, layout, Camera(), ConePoseConfig(), pred);
    ASSERT_TRUE(cp.ok) << cp.error;
    EXPECT_EQ(cp.cone_of_detection, (std::vector<int>{2, 0, 1}));
    EXPECT_EQ(Associate(dets, layout, pred).cone_of_detection, cp.cone_of_detection);
  }
}

// rig_sim's camera at 512x384 (undistorted pixels).
CameraModel RigSim512() {
  CameraModel cam;
  cam.width_px = 512, cam.height_px = 384, cam.fx_px = 385, cam.fy_px = 388, cam.cx_px = 255.5, cam.cy_px = 191.5;
  return cam;
}

// T_camera_cones of a camera at eye (in `cones`) turned by q_cones_camera, as rig_sim/ground_truth and pose_ekf/pose
// give it.
pose_math::Pose CameraAt(const Eigen::Vector3d& eye, const Eigen::Quaterniond& q_cones_camera) {
  pose_math::Pose T;
  const Eigen::Matrix3d R = q_cones_camera.toRotationMatrix().transpose();
  T.q = pose_math::QuatFromRotation(R), T.t = -(R * eye);
  return T;
}

// The association's prior as cone_tracker's node makes it from pose_ekf/pose (orientation q_pred, ROS covariance):
// the filter's covariance plus 2 degrees and 5 cm.
AssociationConfig RecordedPrior(const Eigen::Quaterniond& q_pred, const Eigen::Matrix<double, 6, 6>& cov_ros) {
  AssociationConfig cfg;
  cfg.prediction_cov = AssociationPrior(pose_math::Quat(q_pred.w(), q_pred.x(), q_pred.y(), q_pred.z()), cov_ros);
  cfg.prediction_cov->diagonal() +=
      (Eigen::Matrix<double, 6, 1>() << Eigen::Vector3d::Constant(std::pow(2.0 * M_PI / 180.0, 2)),
       Eigen::Vector3d::Constant(0.05 * 0.05))
          .finished();
  return cfg;
}

// Negative information (AssociationConfig::miss_cost, rig_model/cone_view.h). rig_sim's look_away seed 8 at
// 512x384, 12.833 s: the first frame after the 7 s outage, pose_ekf 0.29 m off with a position sigma of about
// 0.5 m (its recorded pose and covariance), one cone in the image: the tall cone 1 near the right edge. Read as
// the short cone 2, 0.7 m nearer and lower (fit 3.1 against 0.2), it is ambiguous, and three frames went
// unfused. But that reading puts cone 1 itself in the middle of the image, where nothing was detected: with the
// cost of a miss it is no rival. And a miss alone never makes a wrong cone win: with cone 0 hidden (not
// detected) beside cone 1, cone 1's own reading pays the miss and is at worst ambiguous, never renamed.
TEST(Associate, AConeAReadingPutsInPlainViewUnseenCostsThatReadingAMiss) {
  const auto layout = Asymmetric();
  const CameraModel cam = RigSim512();
  const Eigen::Vector3d eye(-2.1401, -2.3350, 1.3767);
  const pose_math::Pose truth = CameraAt(eye, Eigen::Quaterniond(0.57329, -0.81781, -0.00050, 0.05031).normalized());
  const Eigen::Vector3d pred_eye(-1.8812, -2.2713, 1.2700);
  const Eigen::Quaterniond q_pred = Eigen::Quaterniond(0.57342, -0.81771, 0.00361, 0.05030).normalized();
  Eigen::Matrix<double, 6, 6> cov_ros = Eigen::Matrix<double, 6, 6>::Zero();  // pose_ekf/pose's, rounded
  cov_ros.topLeftCorner<3, 3>() << 0.2884, 0.0452, 0.0187, 0.0452, 0.2723, -0.0380, 0.0187, -0.0380, 0.2126;
  cov_ros.bottomRightCorner<3, 3>() << 5.98e-6, 3.6e-7, 8.0e-7, 3.6e-7, 5.46e-6, 2.48e-6, 8.0e-7, 2.48e-6, 1.307e-5;
  const pose_math::Pose pred = CameraAt(pred_eye, q_pred);
  const AssociationConfig cfg = RecordedPrior(q_pred, cov_ros);
  // Cone `id`'s peak, mid and base as the camera T at `from` sees them (exactly).
  const auto seen = [&](const pose_math::Pose& T, const Eigen::Vector3d& from, int id) {
    const auto p = CorrectedModelPoints(layout[size_t(id)], from);
    ConePoints2d d;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d c = pose_math::Transform(T, p[size_t(i)]);
      d[size_t(i)] = Eigen::Vector2d(cam.fx_px * c.x() / c.z() + cam.cx_px, cam.fy_px * c.y() / c.z() + cam.cy_px);
    }
    return d;
  };
  // The detections associated from the prediction T with configuration c.
  const auto associate_with = [&](const std::vector<ConePoints2d>& dets, const AssociationConfig& c,
                                  const pose_math::Pose& T) {
    std::vector<std::array<Eigen::Matrix2d, 3>> cov;
    for (const ConePoints2d& d : dets) {
      const double h = (d[0] - d[2]).norm();
      cov.push_back(PointCovariances(d, h * h * layout[1].tau, c.sigma_px));
    }
    return AssociateCones(dets, cov, layout.size(), LayoutSeenFrom(layout), cam, T, c);
  };
  const auto associate = [&](const std::vector<ConePoints2d>& dets, double miss_cost) {
    AssociationConfig c = cfg;
    c.miss_cost = miss_cost;
    return associate_with(dets, c, pred);
  };
  const ConePoints2d cone1 = seen(truth, eye, 1);
  ASSERT_GT(cone1[0].x(), 400.0) << "cone 1 near the right edge, as in the recording (503, 120)";
  const AssociationResult without = associate({cone1}, 0.0);
  EXPECT_EQ(without.cone_of_detection, (std::vector<int>{-1}));
  EXPECT_EQ(without.ambiguous, 1);
  const AssociationResult with = associate({cone1}, 7.0);  // rig_sim's association_miss_cost
  EXPECT_EQ(with.cone_of_detection, (std::vector<int>{1}));
  EXPECT_EQ(with.misses, 0);
  std::printf("[ miss ] look_away seed 8, 12.833 s: cone 1 alone, without misses %s, with misses cone %d (cost %.2f)\n",
              without.ambiguous ? "ambiguous" : "associated", with.cone_of_detection[0], with.cost);
  // The safety of a miss: from a pose that sees cones 0 and 1 apart, cone 0 undetected (hidden by a person).
  const Eigen::Vector3d eye2(2.8, 2.6, 1.3), target2(0.3, 0.4, 0.3);
  const pose_math::Pose both = LookAt(eye2, target2);
  std::vector<std::optional<rig_model::ImageBox>> boxes;
  for (int id = 0; id < 3; ++id) {
    const ConePoints2d d = seen(both, eye2, id);
    boxes.push_back(rig_model::SilhouetteBox(d[0], d[2], layout[size_t(id)].tau * (d[0] - d[2]).norm()));
  }
  ASSERT_TRUE(rig_model::InPlainView(boxes, cam.width_px, cam.height_px)[0]) << "cone 0 in plain view";
  for (double sigma_m : {0.05, 0.5, 1.5}) {
    AssociationConfig c = cfg;
    c.prediction_cov.reset();
    c.prediction_sigma_m = sigma_m;
    c.miss_cost = 7.0;
    const AssociationResult a = associate_with({seen(both, eye2, 1)}, c, both);
    EXPECT_TRUE(a.cone_of_detection[0] == 1 || a.cone_of_detection[0] == -1)
        << "sigma " << sigma_m << " m: cone 1 named cone " << a.cone_of_detection[0];
  }
}

// The orange regions of a cone's silhouette as the segmenter reports them (SegmentationResult::orange_undist_px):
// boxes around four bands of its rows.
std::vector<rig_model::ImageBox> Slabs(const rig_model::ConeSilhouette& s) {
  std::vector<rig_model::ImageBox> out;
  for (int i = 0; i < kOrangeSlabs; ++i) {
    const double f0 = double(i) / kOrangeSlabs, f1 = double(i + 1) / kOrangeSlabs;
    const Eigen::Vector2d a = s.peak_px + f0 * (s.base_px - s.peak_px), b = s.peak_px + f1 * (s.base_px - s.peak_px);
    out.push_back(rig_model::SilhouetteBox(a, b, f1 * s.half_width_px));
  }
  return out;
}

// Negative information for a cone partly in view (rig_model::MissedInView). rig_sim's look_away seed 69 at 512x384,
// 12.867 s, the first frame after the outage: pose_ekf 0.32 m off (its recorded pose and covariance), the tall
// cone 1 accepted near the right edge, the short cone 2 below it refused (by the tip check). Read as cone 2, with
// the camera 0.6 m away, cone 1 fits nearly as well (ambiguous: the frame went unfused), and that reading puts cone
// 1 above it, cut by the right edge and touching cone 2's silhouette: not in plain view, no miss. But the image has
// no orange there: with the orange regions that reading pays a miss, and the cone is associated. Orange over that
// spot (an orange sign) takes the miss away again: ambiguous, never renamed.
TEST(Associate, AReadingThatPutsAConePartlyInViewWhereNoOrangeIsCostsAMiss) {
  const auto layout = Asymmetric();
  const CameraModel cam = RigSim512();
  const Eigen::Vector3d eye(-1.0780, -2.9265, 1.3758);
  const pose_math::Pose truth = CameraAt(eye, Eigen::Quaterniond(0.55786, -0.80518, -0.13912, 0.14533).normalized());
  const Eigen::Quaterniond q_pred = Eigen::Quaterniond(0.55646, -0.80564, -0.13986, 0.14742).normalized();
  const pose_math::Pose pred = CameraAt(Eigen::Vector3d(-0.92748, -2.65288, 1.32011), q_pred);
  Eigen::Matrix<double, 6, 6> cov_ros = Eigen::Matrix<double, 6, 6>::Zero();  // pose_ekf/pose's, rounded
  cov_ros.topLeftCorner<3, 3>() << 0.1545, 0.0081, 0.0076, 0.0081, 0.1725, -0.0078, 0.0076, -0.0078, 0.1297;
  cov_ros.bottomRightCorner<3, 3>() << 3.95e-6, 2.2e-7, 0.0, 2.2e-7, 3.99e-6, 7.8e-7, 0.0, 7.8e-7, 6.07e-6;
  AssociationConfig cfg = RecordedPrior(q_pred, cov_ros);
  cfg.miss_cost = 7.0;  // rig_sim's association_miss_cost
  const auto silhouettes =
      LayoutSilhouettes(LayoutSeenFrom(layout), layout.size(), pose_math::RotationFromQuat(truth.q), eye, cam, 0.1);
  ASSERT_TRUE(silhouettes[1] && silhouettes[2]);
  const rig_model::ConeSilhouette cone1 = *silhouettes[1], cone2 = *silhouettes[2];
  ASSERT_GT(cone1.peak_px.x(), 480.0) << "cone 1 near the right edge, as in the recording (497, 115)";
  ASSERT_GT(cone2.base_px.y(), cone1.base_px.y()) << "cone 2 below it";
  const ConePoints2d det = {cone1.peak_px, 0.5 * (cone1.peak_px + cone1.base_px), cone1.base_px};
  const double h = (det[0] - det[2]).norm();
  const std::vector<std::array<Eigen::Matrix2d, 3>> cov = {PointCovariances(det, h * h * layout[1].tau, 1.0)};
  const auto associate = [&](const std::vector<rig_model::ImageBox>& orange) {
    return AssociateCones({det}, cov, layout.size(), LayoutSeenFrom(layout), cam, pred, cfg, orange);
  };
  const AssociationResult plain = associate({});  // plain view only
  EXPECT_EQ(plain.cone_of_detection, (std::vector<int>{-1}));
  EXPECT_EQ(plain.ambiguous, 1);
  std::vector<rig_model::ImageBox> orange = Slabs(cone1);
  for (const rig_model::ImageBox& b : Slabs(cone2)) orange.push_back(b);
  const AssociationResult with = associate(orange);
  EXPECT_EQ(with.cone_of_detection, (std::vector<int>{1}));
  EXPECT_EQ(with.misses, 0);
  orange.push_back({cone1.peak_px.x() - 40.0, 0.0, 511.0, cone1.peak_px.y()});  // a sign above cone 1
  const AssociationResult sign = associate(orange);
  EXPECT_EQ(sign.cone_of_detection, (std::vector<int>{-1}));
  EXPECT_EQ(sign.ambiguous, 1);
  std::printf(
      "[ miss ] look_away seed 69, 12.867 s: cone 1 alone, plain view only %s, with the orange cone %d, with "
      "a sign above it %s\n",
      plain.ambiguous ? "ambiguous" : "associated", with.cone_of_detection[0],
      sign.ambiguous ? "ambiguous" : "associated");
}

// The recorded orange regions of look_away seed 35 at 12.833 s (cone_tracker/observations' `orange`, undistorted px):
// four one-pixel columns at the right edge (cone 1's base, cut by it; a barrel lens puts its pixels past the pinhole
// image's edge, and OrangeRegions keeps them on it), then cone 2's blobs, its base cut by the bottom edge.
std::vector<rig_model::ImageBox> LookAway35Orange(bool with_the_edge) {
  const int rois[][4] = {{511, 221, 1, 14},  {511, 233, 1, 13},  {511, 244, 1, 14}, {511, 256, 1, 14},
                         {484, 315, 11, 14}, {481, 327, 12, 14}, {469, 338, 5, 14}, {468, 350, 20, 15},
                         {454, 364, 30, 15}, {447, 374, 37, 10}, {441, 383, 42, 1}, {441, 383, 40, 1}};
  std::vector<rig_model::ImageBox> out;
  for (int i = with_the_edge ? 0 : 4; i < 12; ++i)  // rig_model::FromRoi's boxes
    out.push_back({rois[i][0] - 0.5, rois[i][1] - 0.5, rois[i][0] + rois[i][2] - 0.5, rois[i][1] + rois[i][3] - 0.5});
  return out;
}

// The converse of a miss: orange a reading leaves to clutter (rig_model::UnexplainedOrange). rig_sim's look_away
// seed 35 at 512x384, 12.833 s, the first frame after the outage: pose_ekf 0.42 m off (its recorded pose and
// covariance), the short cone 2 alone (its recorded points: its base cut by the bottom edge, read by its collars,
// collar_ruler.h). Read as the tall cone 1, with the camera 0.9 m away, it fits nearly as well: ambiguous. The
// frame's other orange is cone 1's base at the right edge: the right reading puts cone 1 there, the other leaves it
// to clutter and pays for it. Without that orange, no cue.
TEST(Associate, AReadingThatLeavesOrangeUnexplainedPaysForIt) {
  const auto layout = Asymmetric();
  const CameraModel cam = RigSim512();
  const Eigen::Quaterniond q_pred = Eigen::Quaterniond(0.54092, -0.77679, -0.28805, 0.14503).normalized();
  const pose_math::Pose pred = CameraAt(Eigen::Vector3d(-0.51267, -1.96317, 1.19291), q_pred);
  Eigen::Matrix<double, 6, 6> cov_ros = Eigen::Matrix<double, 6, 6>::Zero();  // pose_ekf/pose's, rounded
  cov_ros.topLeftCorner<3, 3>() << 0.1520, 0.0082, 0.0055, 0.0082, 0.1715, -0.0075, 0.0055, -0.0075, 0.1232;
  cov_ros.bottomRightCorner<3, 3>() << 3.96e-6, 3.0e-7, 9.0e-8, 3.0e-7, 3.98e-6, 7.7e-7, 9.0e-8, 7.7e-7, 6.18e-6;
  AssociationConfig cfg = RecordedPrior(q_pred, cov_ros);
  cfg.miss_cost = 7.0;  // rig_sim's association_miss_cost
  const ConePoints2d det = {Eigen::Vector2d(493.74, 312.85), Eigen::Vector2d(473.18, 365.89),
                            Eigen::Vector2d(453.80, 415.88)};
  const double h = (det[0] - det[2]).norm();
  const std::vector<std::array<Eigen::Matrix2d, 3>> cov = {PointCovariances(det, h * h * layout[2].tau, 1.0)};
  const auto associate = [&](double unexplained_cost, bool with_the_edge) {
    AssociationConfig c = cfg;
    c.unexplained_cost = unexplained_cost;
    return AssociateCones({det}, cov, layout.size(), LayoutSeenFrom(layout), cam, pred, c,
                          LookAway35Orange(with_the_edge));
  };
  const AssociationResult off = associate(0.0, true);
  EXPECT_EQ(off.cone_of_detection, (std::vector<int>{-1}));
  EXPECT_EQ(off.ambiguous, 1);
  const AssociationResult on = associate(1.75, true);  // rig_sim's association_unexplained_cost
  EXPECT_EQ(on.cone_of_detection, (std::vector<int>{2}));
  const AssociationResult none = associate(1.75, false);
  EXPECT_EQ(none.cone_of_detection, (std::vector<int>{-1}));
  EXPECT_EQ(none.ambiguous, 1);
  std::printf(
      "[ clutter ] look_away seed 35, 12.833 s: cone 2 alone, without the clutter cost %s, with it cone %d (cost "
      "%.2f), without the orange at the edge %s\n",
      off.ambiguous ? "ambiguous" : "associated", on.cone_of_detection[0], on.cost,
      none.ambiguous ? "ambiguous" : "associated");
}

TEST(PointCovariances, IsotropicButThePeakAlongTheAxis) {
  const double sigma = 1.5;
  // A cone leaning 30 degrees from vertical in the image, 40 px tall, base 2/7 of that.
  const Eigen::Vector2d axis(std::sin(M_PI / 6), -std::cos(M_PI / 6));
  const Eigen::Vector2d base(100, 200), peak = base + 40.0 * axis;
  const double area = 0.5 * 40.0 * (40.0 * 2.0 / 7.0);
  const auto cov = PointCovariances({peak, 0.5 * (peak + base), base}, area, sigma);
  EXPECT_TRUE(cov[1].isApprox(sigma * sigma * Eigen::Matrix2d::Identity()));
  EXPECT_TRUE(cov[2].isApprox(sigma * sigma * Eigen::Matrix2d::Identity()));
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov[0]);
  EXPECT_NEAR(es.eigenvalues()[0], sigma * sigma, 1e-9);  // across the axis
  const double tip = 3.5;                                 // h / w = 7 / 2
  EXPECT_NEAR(es.eigenvalues()[1], sigma * sigma + tip * tip / 12.0, 1e-9);
  EXPECT_NEAR(std::abs(es.eigenvectors().col(1).dot(axis)), 1.0, 1e-9);
  EXPECT_DOUBLE_EQ(cov[0](0, 1), cov[0](1, 0));
  // No blob area (or a degenerate cone): the plain point noise.
  EXPECT_TRUE(
      PointCovariances({peak, peak, peak}, area, sigma)[0].isApprox(sigma * sigma * Eigen::Matrix2d::Identity()));
  EXPECT_TRUE(
      PointCovariances({peak, base, base}, 0.0, sigma)[0].isApprox(sigma * sigma * Eigen::Matrix2d::Identity()));
}

}  // namespace
}  // namespace cone_tracker
