#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "rig_sim/outage_plan.h"
#include "rig_sim/random_layout.h"
#include "rig_sim/trajectory.h"
#include "test_util.h"

namespace rig_sim {
namespace {

// Cones with a point (peak, mid or base) in the image, and those whole in it at least min_px tall.
struct InView {
  int touching = 0;
  std::set<int> whole_tall;
};

InView ConesInView(const Scenario& s, const TruePose& pose, double min_px) {
  const rig_model::CameraModel& cam = s.camera.model;
  InView v;
  for (size_t k = 0; k < s.scene.cones.size(); ++k) {
    const ConeSpec& c = s.scene.cones[k];
    int inside = 0;
    Eigen::Vector2d uv[3];
    const Eigen::Vector3d pts[3] = {c.peak_m(), c.mid_m(), c.base_m};
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d pc = pose.R_cones_camera.transpose() * (pts[i] - pose.p_camera_in_cones_m);
      // The pinhole image first: far off the axis the lens polynomial folds back.
      if (pc.z() < 0.05 || std::abs(pc.x() / pc.z()) > 1.0 || std::abs(pc.y() / pc.z()) > 1.0) continue;
      if (cam.Project(pc, &uv[i]) && uv[i].x() >= 0 && uv[i].y() >= 0 && uv[i].x() < cam.width_px &&
          uv[i].y() < cam.height_px)
        ++inside;
    }
    if (inside > 0) ++v.touching;
    if (inside == 3 && (uv[0] - uv[2]).norm() >= min_px) v.whole_tall.insert(static_cast<int>(k));
  }
  return v;
}

}  // namespace

TEST(OutagePlan, SiteLookAwayLooksDownAtNoConeThenAtExactlyTwo) {
  for (uint64_t seed : {1u, 4u, 6u}) {
    const Scenario s = TestScenario("site_look_away", seed, 0, 0);  // full size: the plan's pixels
    Scenario copy = s;
    std::vector<PlannedOutage> planned;
    std::string err;
    ASSERT_TRUE(PlanOutages(OutagePlanConfig(), &copy, &planned, &err)) << err;
    ASSERT_EQ(planned.size(), 2u);
    const Trajectory traj(s.trajectory);  // the scenario's own: the same plan
    const double ramp_s = OutagePlanConfig().ramp_s;
    for (const PlannedOutage& o : planned) {
      EXPECT_GE(o.away_s, 2.0);
      EXPECT_LE(o.away_s, 8.0);
      for (double t = o.away_start_s + ramp_s; t < o.pair_turn_s; t += 0.1)
        ASSERT_EQ(ConesInView(s, traj.At(t), 0.0).touching, 0) << "seed " << seed << " looking down at " << t << " s";
      for (double t = o.pair_turn_s + ramp_s; t <= o.pair_end_s; t += 0.1) {
        const InView v = ConesInView(s, traj.At(t), 24.0);  // OutagePlanConfig::other_max_px
        EXPECT_EQ(v.whole_tall, (std::set<int>{o.cone_a, o.cone_b})) << "seed " << seed << " at " << t << " s";
      }
      // No turn faster than the plan's limit (a slerp the other way round would jump).
      for (double t = o.away_start_s; t < o.pair_end_s + ramp_s; t += 0.01)
        ASSERT_LT(traj.OmegaCamera(t).norm() * 180.0 / M_PI, OutagePlanConfig().max_rate_deg_s + 1.0)
            << "seed " << seed << " at " << t << " s";
      // The walk's own view returns after the pair's hold, the walk's position all along.
      const double back_s = o.pair_end_s + ramp_s + 0.1;
      TrajectoryConfig walk = s.trajectory;
      walk.segments.erase(std::remove_if(walk.segments.begin(), walk.segments.end(),
                                         [](const Segment& g) { return g.kind == SegmentKind::kLookAt; }),
                          walk.segments.end());
      EXPECT_TRUE(traj.At(back_s).R_cones_camera.isApprox(Trajectory(walk).At(back_s).R_cones_camera, 1e-9));
      EXPECT_TRUE(traj.At(o.pair_turn_s)
                      .p_camera_in_cones_m.isApprox(Trajectory(walk).At(o.pair_turn_s).p_camera_in_cones_m, 1e-12));
    }
  }
}

TEST(OutagePlan, ACutWalkIsTheFirstPartOfTheFullOneOutagesIncluded) {
  const Scenario full = TestScenario("site_look_away", 2, 0, 0), cut = TestScenario("site_look_away", 2, 24.0, 0.5);
  const Trajectory a(full.trajectory), b(cut.trajectory);
  for (double t = 0.0; t < 24.0; t += 0.25) {
    EXPECT_TRUE(a.At(t).p_camera_in_cones_m.isApprox(b.At(t).p_camera_in_cones_m, 1e-12)) << t;
    EXPECT_TRUE(a.At(t).R_cones_camera.isApprox(b.At(t).R_cones_camera, 1e-12)) << t;
  }
}

TEST(OutagePlan, ALayoutWithoutALoneTwoConeViewIsRefusedNamingTheOutage) {
  Scenario s = TestScenario("site_look_away", 1, 0, 0);
  RandomLayoutConfig dense;  // 30 cones in 19 m x 19 m: some third cone is always in the pair's view
  dense.cones = 30;
  dense.seed = 2;
  dense.side_m = 19.0;
  s.scene = RandomLayout(dense);
  const auto before = s.trajectory.segments.size();
  std::string err;
  EXPECT_FALSE(FitTrajectoryToScene(&s, &err));
  EXPECT_NE(err.find("site_look_away: no view of exactly two cones found for an outage starting at"), std::string::npos)
      << err;
  EXPECT_NE(err.find("30 cones"), std::string::npos) << err;
  EXPECT_EQ(s.trajectory.segments.size(), before);
}

TEST(OutagePlan, LookAtSegmentsNeedLooksThatTurnInTime) {
  TrajectoryConfig c;
  Segment seg;
  seg.kind = SegmentKind::kLookAt;
  seg.start_s = 5.0;
  seg.duration_s = 6.0;
  seg.ramp_s = 1.0;
  c.segments = {seg};
  EXPECT_NE(c.Validate().find("no looks"), std::string::npos) << c.Validate();
  c.segments[0].looks = {{0.0, Eigen::Vector3d(1, 0, 0), false}, {0.5, Eigen::Vector3d(0, 1, 0), false}};
  EXPECT_NE(c.Validate().find("looks[0]"), std::string::npos) << c.Validate();
  c.segments[0].looks[1].start_s = 2.0;
  EXPECT_EQ(c.Validate(), "");
}

}  // namespace rig_sim
