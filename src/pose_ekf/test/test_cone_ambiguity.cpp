// The lone-cone ambiguity test of the per-cone update (cone_update.cpp's step 1b): a rival layout cone
// found by the iterated fit (ConeFitCost), its lower bound (ConeFitLowerBound), and the negative information of
// cones a reading puts in plain view (ConesMissedAt). The update itself and its gates: test_cone_update.cpp.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "pose_ekf/core/cone_measurement.h"
#include "pose_ekf/core/ekf_core.h"
#include "pose_ekf/testing/synthetic_cones.h"
#include "pose_ekf/testing/synthetic_rig.h"
#include "pose_math/quaternion.h"
#include "pose_math/rotation.h"

namespace pose_ekf_test {
namespace {

using pose_ekf::ConeFrame;
using pose_ekf::ConeFrameResult;
using pose_ekf::EkfConfig;
using pose_ekf::EkfCore;
using pose_ekf::StateVector;
using pose_ekf::UpdateResult;

// The filter's own check of a lone cone's id: with the position sigma of a long outage (1.5 m per axis,
// look_away seed 4 after 7 s) another layout cone fits the same pixels nearly as well (ambiguous, not
// fused); at a tracked filter's sigma none does, and every lone cone of the runs above was fused. The
// rival is tested on the filter's linearisation (as the gate), so the layout here has a second cone
// 0.4 m beside cone 1, a shift the linearisation holds (a rival 1.5 m away is judged, too strictly,
// by its first-order shape change: README, "Re-acquisition").
TEST(ConeGates, ALoneConeAnotherLayoutConeFitsIsNotFused) {
  const auto run = [](double margin, double sigma_p_m, ConeFrameResult* r) {
    EkfConfig c = ConeSimConfig();
    c.cone_ambiguity_margin = margin;
    EkfCore ekf = Tight(c, sigma_p_m);
    std::mt19937 rng(11);
    std::vector<pose_ekf::ConeGeometry> layout = DefaultCones();
    layout.push_back(layout[1]);
    layout.back().base_m += Eigen::Vector3d(0.0, 0.4, 0.0);
    const UpdateResult u =
        ekf.UpdateCones(ObserveCones(0.0, ConeRigStart(), layout, {1}, DefaultIntrinsics(), 1.0, &rng), r);
    std::printf("[ cones ] lone cone, position sigma %.2f m, margin %.0f: %s\n", sigma_p_m, margin, ToString(u));
    return u;
  };
  ConeFrameResult r;
  EXPECT_EQ(run(9.0, 0.02, &r), UpdateResult::kApplied);
  EXPECT_EQ(r.ambiguous, 0);
  EXPECT_EQ(run(9.0, 1.5, &r), UpdateResult::kGated);
  EXPECT_EQ(r.ambiguous, 1);
  EXPECT_EQ(run(0.0, 1.5, &r), UpdateResult::kApplied);  // the test off
  EXPECT_EQ(r.ambiguous, 0);
}

// A rival that needs a pose correction comparable to its distance (look_away_recovery seed 5 at 256x192
// read cone 1 as cone 2 at a position sigma of 1.7 m): a shorter cone (0.65 of the height) placed so that a
// camera 1.3 m from the prediction sees it exactly as the prediction sees the observed cone. The
// first-order statistic judges it by the linearisation at the prediction, where it looks smaller and
// elsewhere, and scores it far off, so the lone cone was fused; the iterated fit (ConeFitCost) finds the
// 1.3 m correction, whose Mahalanobis distance under that sigma is ~1, and the frame is refused (other
// directions of the shift: first order 0.8-21 700, iterated 0.8-3.0 for 1.3-2.5 m). At a
// tracked filter's sigma the rival's fit is hopeless either way and the cone is fused.
TEST(ConeGates, AFarRivalIsFoundByTheIteratedFit) {
  const pose_math::Pose start = ConeRigStart();
  const double k = 0.65;
  std::vector<pose_ekf::ConeGeometry> layout = {DefaultCones()[1], DefaultCones()[1]};
  // The camera 1.2 m further back (it looks along +y) and lower, so that the rival stands on the ground.
  const Eigen::Vector3d shift(0.0, -1.2, -(1.0 - k) * (start.t.z() - layout[0].base_m.z()));
  layout[1].base_m = start.t + shift + k * (layout[0].base_m - start.t);
  layout[1].height_m = k * layout[0].height_m;
  double rival_fit = 0.0;  // the rival's ConeFitCost, fitted or not by UpdateCones
  const auto run = [&](int iterations, double sigma_p_m, ConeFrameResult* r) {
    EkfConfig c = ConeSimConfig();
    c.cone_ambiguity_iterations = iterations;
    EkfCore ekf = Tight(c, sigma_p_m);
    std::mt19937 rng(11);
    const ConeFrame f = ObserveCones(0.0, start, layout, {0}, DefaultIntrinsics(), 1.0, &rng);
    rival_fit = pose_ekf::ConeFitCost(ekf.state().x, ekf.state().P, layout[1], f.K, pose_ekf::ConePixels(f.cones[0]),
                                      pose_ekf::ConeCovariance(f.cones[0]), iterations);
    const UpdateResult u = ekf.UpdateCones(f, r);
    std::printf(
        "[ cones ] far rival (%.2f m away), %d iterations, position sigma %.2f m: own %.2f, rival %.2f (%d screened, "
        "fit %.2f) -> %s\n",
        shift.norm(), iterations, sigma_p_m, r->ambiguity_own_chi2, r->ambiguity_rival_chi2, r->ambiguity_screened,
        rival_fit, ToString(u));
    return u;
  };
  ConeFrameResult r;
  EXPECT_EQ(run(0, 1.5, &r), UpdateResult::kApplied);  // first order: the rival is missed
  EXPECT_EQ(r.ambiguity_rival_id, 1);
  EXPECT_GT(r.ambiguity_rival_chi2 - r.ambiguity_own_chi2, 9.0);
  EXPECT_EQ(run(5, 1.5, &r), UpdateResult::kGated);  // iterated: ambiguous, not fused
  EXPECT_EQ(r.ambiguous, 1);
  EXPECT_EQ(r.ambiguity_rival_id, 1);
  EXPECT_LT(r.ambiguity_rival_chi2, 5.0);
  EXPECT_LT(r.ambiguity_own_chi2, 5.0);
  EXPECT_EQ(run(5, 0.02, &r), UpdateResult::kApplied);  // tracked: no rival
  EXPECT_EQ(r.ambiguous, 0);
  EXPECT_GT(rival_fit - r.ambiguity_own_chi2, 1000.0);
  EXPECT_EQ(r.ambiguity_screened, 1);  // ConeFitLowerBound ruled it out without fitting it
}

// rig_model's asymmetric.yaml, and rig_sim's camera at 512x384.
std::vector<pose_ekf::ConeGeometry> AsymmetricLayout() {
  std::vector<pose_ekf::ConeGeometry> layout(3);
  layout[0].base_m = {1.00, 0.00, 0}, layout[1].base_m = {-0.40, 0.85, 0}, layout[2].base_m = {-0.60, -0.85, 0};
  layout[2].height_m = 0.46;
  return layout;
}
const pose_ekf::PinholeIntrinsics kRigSim512{385.0, 388.0, 255.5, 191.5};

// The filter as a recording left it: pose_ekf/pose's pose and position covariance, with rig_sim's miss cost.
EkfCore Recorded(const pose_math::Pose& T_cones_camera, const Eigen::Matrix3d& position_cov, double miss_cost,
                 double unexplained_cost = 0.0) {
  EkfConfig c = ConeSimConfig();
  c.cone_miss_cost = miss_cost, c.cone_unexplained_cost = unexplained_cost;
  EkfCore ekf{c};
  EXPECT_TRUE(ekf.Initialize(Camera(0.0, T_cones_camera, 0.0024, 0.01)));
  pose_ekf::FilterState s = ekf.state();
  s.P.block<3, 3>(pose_ekf::kP, pose_ekf::kP) = position_cov;
  ekf.Restore(s);
  return ekf;
}

// Negative information (EkfConfig::cone_miss_cost, rig_model/cone_view.h). rig_sim's look_away seed 8 at
// 512x384, 12.833 s, the first frame after its 7 s outage: pose_ekf 0.29 m off (its recorded pose and position
// covariance), the tall cone 1 alone near the right edge of the image. Read as the short cone 2, 0.7 m nearer and
// lower, it fits nearly as well: ambiguous, not fused. But that reading's pose puts cone 1 itself in plain view,
// where the frame has no cone: with the cost of that miss the lone cone is fused. Without the image size (an
// older tracker) there is no negative information.
TEST(ConeGates, ARivalThatPutsAnUnseenConeInPlainViewPaysAMiss) {
  const std::vector<pose_ekf::ConeGeometry> layout = AsymmetricLayout();
  const pose_ekf::PinholeIntrinsics K = kRigSim512;
  pose_math::Pose truth, predicted;  // T_cones_camera
  truth.q = pose_math::Quat(0.57329, -0.81781, -0.00050, 0.05031).normalized(), truth.t = {-2.1401, -2.3350, 1.3767};
  predicted.q = pose_math::Quat(0.57342, -0.81771, 0.00361, 0.05030).normalized();
  predicted.t = {-1.8812, -2.2713, 1.2700};
  Eigen::Matrix3d position_cov;  // pose_ekf/pose's, rounded
  position_cov << 0.2884, 0.0452, 0.0187, 0.0452, 0.2723, -0.0380, 0.0187, -0.0380, 0.2126;
  const auto run = [&](double miss_cost, bool image_size, ConeFrameResult* r) {
    EkfCore ekf = Recorded(predicted, position_cov, miss_cost);
    std::mt19937 rng(11);
    ConeFrame f = ObserveCones(0.0, truth, layout, {1}, K, 0.3, &rng);
    f.layout = layout;
    if (image_size) f.width_px = 512, f.height_px = 384;
    const UpdateResult u = ekf.UpdateCones(f, r);
    std::printf(
        "[ cones ] look_away seed 8, 12.833 s, miss cost %.0f%s: own %.2f (%d missed), rival %.2f (cone %d, %d "
        "missed) -> %s\n",
        miss_cost, image_size ? "" : ", no image size", r->ambiguity_own_chi2, r->ambiguity_own_missed,
        r->ambiguity_rival_chi2, r->ambiguity_rival_id, r->ambiguity_rival_missed, ToString(u));
    return u;
  };
  ConeFrameResult r;
  EXPECT_EQ(run(0.0, true, &r), UpdateResult::kGated);  // off: ambiguous
  EXPECT_EQ(r.ambiguous, 1);
  EXPECT_EQ(r.ambiguity_rival_id, 2);
  EXPECT_EQ(run(7.0, true, &r), UpdateResult::kApplied);  // pose_ekf_rig_sim.yaml's cone_miss_cost
  EXPECT_EQ(r.ambiguous, 0);
  EXPECT_EQ(r.ambiguity_own_missed, 0);
  EXPECT_EQ(r.ambiguity_rival_missed, 1);                // cone 1, from the pose that reads it as cone 2
  EXPECT_EQ(run(7.0, false, &r), UpdateResult::kGated);  // no image size: no negative information
  EXPECT_EQ(r.ambiguity_rival_missed, 0);
  // The truth puts no cone in plain view, seen or not: cone 1 is within the margin of the right edge (a cone
  // there may be cut, and the detector may refuse it), cones 0 and 2 are outside the image. Turned 20 degrees
  // toward them, cones 1 and 2 are in plain view, each a miss unless it was seen.
  StateVector x = Tight(ConeSimConfig(), 0.0).state().x;
  x.segment<4>(pose_ekf::kQ) = truth.q, x.segment<3>(pose_ekf::kP) = truth.t;
  ConeFrame f;
  f.K = K, f.layout = layout, f.width_px = 512, f.height_px = 384;
  EXPECT_EQ(pose_ekf::ConesMissedAt(x, f, {}), 0);
  const Eigen::Matrix3d turned =
      pose_math::RotationFromQuat(truth.q) * Eigen::AngleAxisd(20.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).matrix();
  x.segment<4>(pose_ekf::kQ) = pose_math::QuatFromRotation(turned);
  EXPECT_EQ(pose_ekf::ConesMissedAt(x, f, {}), 2);
  EXPECT_EQ(pose_ekf::ConesMissedAt(x, f, {1}), 1);
  EXPECT_EQ(pose_ekf::ConesMissedAt(x, f, {1, 2}), 0);
}

// Negative information for a cone partly in view (ConeFrame::orange_px, rig_model::MissedInView). rig_sim's
// look_away seed 69 at 512x384, 12.867 s, the first frame after the outage: pose_ekf 0.32 m off (its recorded pose
// and position covariance), the tall cone 1 alone near the right edge (the short cone 2 below it refused by the
// tracker). Read as cone 2, cone 1 fits nearly as well, and that reading puts cone 1 above it, cut by the right
// edge: not in plain view, no miss, not fused. The frame's orange regions (cones 1 and 2 as they are, in four bands
// of rows each as cone_tracker reports them) show none there: that reading pays a miss and the cone is fused.
TEST(ConeGates, ARivalThatPutsAnUnseenConePartlyInViewWhereNoOrangeIsPaysAMiss) {
  const std::vector<pose_ekf::ConeGeometry> layout = AsymmetricLayout();
  const pose_ekf::PinholeIntrinsics K = kRigSim512;
  pose_math::Pose truth, predicted;  // T_cones_camera
  truth.q = pose_math::Quat(0.55786, -0.80518, -0.13912, 0.14533).normalized(), truth.t = {-1.0780, -2.9265, 1.3758};
  predicted.q = pose_math::Quat(0.55646, -0.80564, -0.13986, 0.14742).normalized();
  predicted.t = {-0.92748, -2.65288, 1.32011};
  Eigen::Matrix3d position_cov;  // pose_ekf/pose's, rounded
  position_cov << 0.1545, 0.0081, 0.0076, 0.0081, 0.1725, -0.0078, 0.0076, -0.0078, 0.1297;
  StateVector x_true = Tight(ConeSimConfig(), 0.0).state().x;
  x_true.segment<4>(pose_ekf::kQ) = truth.q, x_true.segment<3>(pose_ekf::kP) = truth.t;
  std::vector<rig_model::ImageBox> orange;
  pose_ekf::ConeVector cone1;
  ASSERT_TRUE(pose_ekf::ProjectCone(x_true, layout[1], K, &cone1, nullptr));
  for (int k : {1, 2}) {
    pose_ekf::ConeVector h;
    ASSERT_TRUE(pose_ekf::ProjectCone(x_true, layout[size_t(k)], K, &h, nullptr));
    const Eigen::Vector2d peak = h.segment<2>(0), axis = h.segment<2>(2) - peak;
    for (int i = 0; i < 4; ++i)  // cone_tracker's kOrangeSlabs
      orange.push_back(rig_model::SilhouetteBox(peak + i / 4.0 * axis, peak + (i + 1) / 4.0 * axis,
                                                (i + 1) / 4.0 * layout[size_t(k)].tau * axis.norm()));
  }
  const auto run = [&](bool with_orange, ConeFrameResult* r) {
    EkfCore ekf = Recorded(predicted, position_cov, 7.0);  // pose_ekf_rig_sim.yaml's cone_miss_cost
    // Cone 1 as the truth projects it (undistorted, its peak beyond u = 511 where ObserveCones would drop it).
    ConeFrame f;
    f.K = K, f.layout = layout, f.width_px = 512, f.height_px = 384;
    f.cones.resize(1);
    f.cones[0].cone_id = 1, f.cones[0].cone = layout[1];
    f.cones[0].px = {cone1.segment<2>(0), 0.5 * (cone1.segment<2>(0) + cone1.segment<2>(2)), cone1.segment<2>(2)};
    for (Eigen::Matrix2d& c : f.cones[0].cov_px2) c = Eigen::Matrix2d::Identity();
    if (with_orange) f.orange_px = orange;
    const UpdateResult u = ekf.UpdateCones(f, r);
    std::printf(
        "[ cones ] look_away seed 69, 12.867 s%s: own %.2f (%d missed), rival %.2f (cone %d, %d missed) -> %s\n",
        with_orange ? ", orange regions" : ", plain view only", r->ambiguity_own_chi2, r->ambiguity_own_missed,
        r->ambiguity_rival_chi2, r->ambiguity_rival_id, r->ambiguity_rival_missed, ToString(u));
    return u;
  };
  ConeFrameResult r;
  EXPECT_EQ(run(false, &r), UpdateResult::kGated);
  EXPECT_EQ(r.ambiguous, 1);
  EXPECT_EQ(r.ambiguity_rival_id, 2);
  EXPECT_EQ(r.ambiguity_rival_missed, 0);
  EXPECT_EQ(run(true, &r), UpdateResult::kApplied);
  EXPECT_EQ(r.ambiguous, 0);
  EXPECT_EQ(r.ambiguity_own_missed, 0);
  EXPECT_EQ(r.ambiguity_rival_missed, 1);  // cone 1, above the detection, where the image has no orange
}

// The converse (EkfConfig::cone_unexplained_cost, rig_model::UnexplainedOrange). rig_sim's look_away seed 35 at
// 512x384, 12.833 s, the first frame after the outage: pose_ekf 0.42 m off (its recorded pose and position
// covariance), the short cone 2 alone (its recorded points: its base cut by the image's bottom edge, read by its
// collars in cone_tracker). Read as the tall cone 1, 0.9 m away, it fits nearly as well: ambiguous. The frame's
// recorded orange regions also hold cone 1's base at the right edge (one-pixel columns: a barrel lens puts its pixels
// past the pinhole image's edge): the right reading puts cone 1 there, the other leaves it to clutter. Without that
// orange, no cue.
TEST(ConeGates, ARivalThatLeavesOrangeUnexplainedPaysForIt) {
  const std::vector<pose_ekf::ConeGeometry> layout = AsymmetricLayout();
  const pose_ekf::PinholeIntrinsics K = kRigSim512;
  pose_math::Pose predicted;  // T_cones_camera
  predicted.q = pose_math::Quat(0.54092, -0.77679, -0.28805, 0.14503).normalized();
  predicted.t = {-0.51267, -1.96317, 1.19291};
  Eigen::Matrix3d position_cov;  // pose_ekf/pose's, rounded
  position_cov << 0.1520, 0.0082, 0.0055, 0.0082, 0.1715, -0.0075, 0.0055, -0.0075, 0.1232;
  const int rois[][4] = {{511, 221, 1, 14},  {511, 233, 1, 13},  {511, 244, 1, 14}, {511, 256, 1, 14},
                         {484, 315, 11, 14}, {481, 327, 12, 14}, {469, 338, 5, 14}, {468, 350, 20, 15},
                         {454, 364, 30, 15}, {447, 374, 37, 10}, {441, 383, 42, 1}, {441, 383, 40, 1}};
  const auto run = [&](double unexplained_cost, bool with_the_edge, ConeFrameResult* r) {
    EkfCore ekf = Recorded(predicted, position_cov, 7.0, unexplained_cost);  // pose_ekf_rig_sim.yaml's: 7, 1.75
    ConeFrame f;
    f.K = K, f.layout = layout, f.width_px = 512, f.height_px = 384;
    f.cones.resize(1);
    f.cones[0].cone_id = 2, f.cones[0].cone = layout[2];
    f.cones[0].px = {Eigen::Vector2d(493.74, 312.85), Eigen::Vector2d(473.18, 365.89), Eigen::Vector2d(453.80, 415.88)};
    for (Eigen::Matrix2d& cov : f.cones[0].cov_px2) cov = Eigen::Matrix2d::Identity();
    for (int i = with_the_edge ? 0 : 4; i < 12; ++i)  // rig_model::FromRoi's boxes
      f.orange_px.push_back(
          {rois[i][0] - 0.5, rois[i][1] - 0.5, rois[i][0] + rois[i][2] - 0.5, rois[i][1] + rois[i][3] - 0.5});
    const UpdateResult u = ekf.UpdateCones(f, r);
    std::printf(
        "[ cones ] look_away seed 35, 12.833 s, unexplained cost %.2f%s: own %.2f (%d unexplained), rival %.2f "
        "(cone %d, %d unexplained) -> %s\n",
        unexplained_cost, with_the_edge ? "" : ", no orange at the right edge", r->ambiguity_own_chi2,
        r->ambiguity_own_unexplained, r->ambiguity_rival_chi2, r->ambiguity_rival_id, r->ambiguity_rival_unexplained,
        ToString(u));
    return u;
  };
  ConeFrameResult r;
  EXPECT_EQ(run(0.0, true, &r), UpdateResult::kGated);  // off: ambiguous
  EXPECT_EQ(r.ambiguous, 1);
  EXPECT_EQ(r.ambiguity_rival_id, 1);
  EXPECT_EQ(run(1.75, true, &r), UpdateResult::kApplied);
  EXPECT_EQ(r.ambiguity_own_unexplained, 0);
  EXPECT_GE(r.ambiguity_rival_unexplained, 2);
  EXPECT_EQ(run(1.75, false, &r), UpdateResult::kGated);  // nothing at the edge to explain: ambiguous again
  EXPECT_EQ(r.ambiguity_rival_unexplained, 0);
}

// ConeFitCost: with 0 iterations the first-order statistic yᵀ S⁻¹ y, and iterated the same figure where
// h is nearly linear over the prior's range (small P). With the camera 0.5 m beside the prediction at a
// position sigma of 0.5 m, the fit is at least as good as the truth itself (prior term 1 plus the
// pixel noise's chi-square), where the first-order figure is not bounded by it.
TEST(ConeGates, ConeFitCostIteratesTheFirstOrderStatistic) {
  EkfCore ekf = Tight(ConeSimConfig());
  pose_ekf::FilterState s = ekf.state();
  std::mt19937 rng(5);
  const pose_ekf::PinholeIntrinsics K = DefaultIntrinsics();
  const auto cost = [&](const ConeFrame& f, int iterations) {
    return pose_ekf::ConeFitCost(s.x, s.P, f.cones[0].cone, K, pose_ekf::ConePixels(f.cones[0]),
                                 pose_ekf::ConeCovariance(f.cones[0]), iterations);
  };
  const ConeFrame near = ObserveCones(0.0, ConeRigStart(), DefaultCones(), {0}, K, 1.0, &rng);
  const double first = cost(near, 0), iterated = cost(near, 5);
  EXPECT_NEAR(iterated, first, 0.01 * first + 1e-6);
  pose_math::Pose moved = ConeRigStart();
  moved.t += Eigen::Vector3d(0.5, 0.0, 0.0);
  const double sigma_p_m = 0.5;
  s.P.block<3, 3>(pose_ekf::kP, pose_ekf::kP) = sigma_p_m * sigma_p_m * Eigen::Matrix3d::Identity();
  const ConeFrame far = ObserveCones(0.0, moved, DefaultCones(), {0}, K, 1.0, &rng);
  StateVector x_true = s.x;
  x_true.segment<3>(pose_ekf::kP) = moved.t;
  ConeVector h_true;
  ASSERT_TRUE(pose_ekf::ProjectCone(x_true, far.cones[0].cone, K, &h_true, nullptr));
  const ConeVector noise = pose_ekf::ConePixels(far.cones[0]) - h_true;
  const double at_truth = 1.0 + noise.dot(pose_ekf::ConeCovariance(far.cones[0]).inverse() * noise);
  const double far_first = cost(far, 0), far_iterated = cost(far, 5);
  std::printf(
      "[ cones ] ConeFitCost, camera 0.5 m off at sigma 0.5 m: first order %.3f, iterated %.3f, J at the truth %.3f\n",
      far_first, far_iterated, at_truth);
  EXPECT_LE(far_iterated, at_truth + 1e-6);
  EXPECT_GT(far_iterated, 0.0);
}

// ConeFitLowerBound (the ambiguity test's screen) never exceeds the fit it bounds: cameras off the prediction by
// about one sigma (position sigma 1 cm to 2 m, rotation sigma 0.06° to 6°), every layout cone scored against one
// cone's pixels, thresholds 1 to 10⁴. And it must save the fits where they are hopeless: at a tracked filter's
// sigmas (≤ 10 cm, ≤ 0.6°) it rules out every other cone at 10 (own fit ~1 plus the default margin 9).
TEST(ConeGates, ConeFitLowerBoundIsBelowTheFit) {
  std::mt19937 rng(17);
  std::normal_distribution<double> normal;
  const pose_ekf::PinholeIntrinsics K = DefaultIntrinsics();
  const std::vector<pose_ekf::ConeGeometry> layout = DefaultCones();
  int bounds = 0, reached = 0, tracked_rivals = 0, tracked_screened = 0;
  for (double sigma_p_m : {0.01, 0.1, 0.5, 2.0}) {
    for (double sigma_rad : {0.001, 0.01, 0.1}) {
      EkfCore ekf = Tight(ConeSimConfig(), sigma_p_m);
      pose_ekf::FilterState s = ekf.state();
      const Eigen::Matrix<double, 4, 3> G = pose_math::RotationPerturbationToQuat(s.x.segment<4>(pose_ekf::kQ));
      s.P.block<4, 4>(pose_ekf::kQ, pose_ekf::kQ) = sigma_rad * sigma_rad * G * G.transpose();
      const bool tracked = sigma_p_m <= 0.1 && sigma_rad <= 0.01;
      for (int trial = 0; trial < 8; ++trial) {
        pose_math::Pose truth = ConeRigStart();
        const Eigen::Vector3d turn(normal(rng), normal(rng), normal(rng)), shift(normal(rng), normal(rng), normal(rng));
        truth.q = pose_math::Multiply(truth.q, pose_math::QuatFromRotationVector(sigma_rad * turn));
        truth.t += sigma_p_m * shift;
        const int seen = trial % 3;
        const ConeFrame f = ObserveCones(0.0, truth, layout, {seen}, K, 1.0, &rng);
        if (f.cones.empty()) continue;
        const ConeVector z = pose_ekf::ConePixels(f.cones[0]);
        const pose_ekf::ConeMatrix R = pose_ekf::ConeCovariance(f.cones[0]);
        for (size_t j = 0; j < layout.size(); ++j) {
          const double fit = pose_ekf::ConeFitCost(s.x, s.P, layout[j], K, z, R, 5);
          for (double t2 : {1.0, 10.0, 100.0, 1e3, 1e4}) {
            const double bound = pose_ekf::ConeFitLowerBound(s.x, s.P, layout[j], K, z, R, t2);
            EXPECT_LE(bound, fit * (1.0 + 1e-9)) << "sigma " << sigma_p_m << " m, " << sigma_rad << " rad, t2 " << t2;
            ++bounds;
            reached += bound >= t2;
          }
          if (tracked && static_cast<int>(j) != seen) {
            ++tracked_rivals;
            tracked_screened += pose_ekf::ConeFitLowerBound(s.x, s.P, layout[j], K, z, R, 10.0) >= 10.0;
          }
        }
      }
    }
  }
  std::printf(
      "[ cones ] ConeFitLowerBound: %d bounds, %d reached their threshold; tracked, %d of %d rivals ruled out\n",
      bounds, reached, tracked_screened, tracked_rivals);
  EXPECT_GT(tracked_rivals, 0);
  EXPECT_EQ(tracked_screened, tracked_rivals);
}

}  // namespace
}  // namespace pose_ekf_test
