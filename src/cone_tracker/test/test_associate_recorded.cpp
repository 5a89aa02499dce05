// The association's negative information on recorded frames of rig_sim's look_away scenario (512x384, the first
// frames after its outage): a cone a reading puts in plain view unseen, or partly in view where the image has no
// orange, and orange a reading leaves to clutter (rig_model/cone_view.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "association_test_util.h"

namespace cone_tracker {
namespace {

using association_test::Asymmetric;
using association_test::CameraAt;
using association_test::PoseLookingAt;
using association_test::RecordedPrior;
using association_test::RigSim512;
using association_test::Slabs;

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
  const pose_math::Pose both = PoseLookingAt(eye2, target2);
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

}  // namespace
}  // namespace cone_tracker
