#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/LU>

#include "rig_sim/camera_model.h"
#include "rig_sim/trajectory.h"
#include "test_util.h"

namespace rig_sim {
namespace {
constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

bool AnyConeInView(const Scenario& s, const TruePose& pose) {
  const rig_model::CameraModel& cam = s.camera.model;
  for (const ConeSpec& c : s.scene.cones) {
    for (const Eigen::Vector3d& p : {c.peak_m(), c.mid_m(), c.base_m}) {
      Eigen::Vector2d uv;
      const Eigen::Vector3d pc = pose.R_cones_camera.transpose() * (p - pose.p_camera_in_cones_m);
      if (cam.Project(pc, &uv) && uv.x() >= 0 && uv.y() >= 0 && uv.x() < s.camera.model.width_px &&
          uv.y() < s.camera.model.height_px)
        return true;
    }
  }
  return false;
}
}  // namespace

TEST(Trajectory, SameSeedSamePosesOtherSeedOtherPoses) {
  const Scenario s = TestScenario("handheld", 7, 0, 0);
  const Trajectory a(s.trajectory), b(s.trajectory);
  TrajectoryConfig other = s.trajectory;
  other.seed = 8;
  const Trajectory c(other);
  EXPECT_EQ(a.At(10.0).p_camera_in_cones_m, b.At(10.0).p_camera_in_cones_m);
  EXPECT_GT((a.At(10.0).p_camera_in_cones_m - c.At(10.0).p_camera_in_cones_m).norm(), 0.05);
}

TEST(Trajectory, HandheldStaysInRangeWithHandheldRatesAndOutOfViewStretch) {
  const Scenario s = TestScenario("handheld", 3, 0, 0.25);
  const Trajectory traj(s.trajectory);
  double min_d = 1e9, max_d = 0, max_rate = 0, out_of_view_s = 0, longest_out_s = 0, run = 0;
  const double dt = 1.0 / 100.0;
  for (double t = 0; t < s.trajectory.duration_s; t += dt) {
    const TruePose p = traj.At(t);
    const Eigen::Vector3d target(0, 0, s.trajectory.look_target_height_m);
    min_d = std::min(min_d, (p.p_camera_in_cones_m - target).norm());
    max_d = std::max(max_d, (p.p_camera_in_cones_m - target).norm());
    max_rate = std::max(max_rate, traj.OmegaCamera(t).norm() * kRadToDeg);
    ASSERT_NEAR(p.R_cones_camera.determinant(), 1.0, 1e-9);
    if (!AnyConeInView(s, p)) {
      out_of_view_s += dt;
      run += dt;
      longest_out_s = std::max(longest_out_s, run);
    } else {
      run = 0;
    }
  }
  EXPECT_GE(min_d, 1.5);
  EXPECT_LE(max_d, 4.0);
  EXPECT_GT(max_d - min_d, 1.0);  // the whole range is used
  EXPECT_GT(max_rate, 150.0);
  EXPECT_LT(max_rate, 260.0);
  EXPECT_GT(longest_out_s, 3.0);   // the gyro-only stretch (7.3)
  EXPECT_LT(out_of_view_s, 10.0);  // but mostly the cones are seen
}

TEST(Trajectory, StillSegmentIsExactlyAtRestAndSmoothAroundIt) {
  const Scenario s = TestScenario("handheld", 3, 0, 0);
  const Trajectory traj(s.trajectory);
  ASSERT_TRUE(traj.IsStill(1.0));
  ASSERT_FALSE(traj.IsStill(10.0));
  const TruePose a = traj.At(0.2), b = traj.At(2.9);
  EXPECT_EQ(a.p_camera_in_cones_m, b.p_camera_in_cones_m);
  EXPECT_LT(traj.OmegaCamera(2.0).norm(), 1e-9);
  // Leaving the still segment the motion starts smoothly: no jump in rate.
  double prev = traj.OmegaCamera(3.0).norm();
  for (double t = 3.0; t < 4.5; t += 0.005) {
    const double w = traj.OmegaCamera(t).norm();
    EXPECT_LT(std::fabs(w - prev), 0.05) << t;
    prev = w;
  }
}

TEST(Trajectory, OverlappingSegmentsAndBadRangesAreRefused) {
  TrajectoryConfig c;
  c.segments = {{SegmentKind::kStill, 1.0, 3.0, 0.5, 0, 0}, {SegmentKind::kShake, 2.0, 3.0, 0.5, 5, 3}};
  EXPECT_NE(c.Validate().find("overlap"), std::string::npos);
  EXPECT_THROW(Trajectory{c}, std::invalid_argument);
  c.segments.clear();
  c.min_distance_m = 5.0;
  EXPECT_NE(c.Validate().find("min_distance_m"), std::string::npos);
}

}  // namespace rig_sim

namespace rig_sim {

TEST(Trajectory, EveryScenarioStaysWithinTheCristaRangesAndItsDistances) {
  for (const ScenarioInfo& info : ListScenarios()) {
    const Scenario s = TestScenario(info.name, 1, 0, 0);
    const Trajectory traj(s.trajectory);
    ImuConfig cfg = s.imu;
    cfg.noise_enabled = false;
    ImuSimulator imu(cfg, traj);
    const int n = static_cast<int>(s.trajectory.duration_s * cfg.rate_hz) - 1;
    for (int k = 0; k < n; ++k) {
      const ImuSample smp = imu.Next();
      ASSERT_FALSE(smp.saturated) << info.name << " at " << smp.stamp_s << " s";
      const TruePose p = traj.At(smp.stamp_s);
      const double d = (p.p_camera_in_cones_m - Eigen::Vector3d(0, 0, s.trajectory.look_target_height_m)).norm();
      ASSERT_GE(d, s.trajectory.min_distance_m) << info.name;
      ASSERT_LE(d, s.trajectory.max_distance_m) << info.name;
      ASSERT_GT(p.p_camera_in_cones_m.z(), 0.1) << info.name;  // never under the ground
    }
  }
}

}  // namespace rig_sim
