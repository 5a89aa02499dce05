// Repeated views (EkfConfig::cone_repeat_px): a still camera's tracker returns the same pixels frame after
// frame, with the same error. Fused as independent, that one error makes the filter sure of itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "pose_ekf/core/cone_measurement.h"
#include "pose_ekf/core/measurement_buffer.h"
#include "pose_ekf/testing/synthetic_cones.h"

namespace pose_ekf_test {
namespace {

using pose_ekf::AddResult;
using pose_ekf::ConeFrame;
using pose_ekf::EkfConfig;
using pose_ekf::FusedConeView;
using pose_ekf::RepeatsView;

TEST(ConeRepeat, TheSameConesWhereTheyWereRepeatTheView) {
  std::mt19937 rng(3);
  const auto cones = DefaultCones();
  const ConeFrame f = ObserveCones(0.0, ConeRigStart(), cones, {0, 1, 2}, DefaultIntrinsics(), 1.0, &rng);
  ASSERT_EQ(f.cones.size(), 3u);
  FusedConeView view;
  EXPECT_FALSE(RepeatsView(view, f, 0.01, 1.0));  // nothing fused yet
  pose_ekf::NoteFusedView(f, {0, 1, 2}, &view);
  ConeFrame g = f;
  g.stamp_s = 0.5;
  EXPECT_TRUE(RepeatsView(view, g, 0.01, 1.0));
  g.cones[1].px[2].x() += 0.005;  // the base, within 0.01 px
  EXPECT_TRUE(RepeatsView(view, g, 0.01, 1.0));
  g.cones[1].px[2].x() += 0.01;  // 0.015 px: the view changed
  EXPECT_FALSE(RepeatsView(view, g, 0.01, 1.0));
  g = f;
  g.stamp_s = 0.5;
  g.cones[0].px[1].y() += 5.0;  // the mid is not a measured point (cone_measurement.h)
  EXPECT_TRUE(RepeatsView(view, g, 0.01, 1.0));
  g.cones.erase(g.cones.begin() + 1);  // fewer cones, where they were: still the same view
  EXPECT_TRUE(RepeatsView(view, g, 0.01, 1.0));
  g.stamp_s = 1.0;  // cone_repeat_max_s after the fused frame: fused again
  EXPECT_FALSE(RepeatsView(view, g, 0.01, 1.0));
  pose_ekf::NoteFusedView(f, {0, 2}, &view);  // cone 1 was not fused: a frame with it is new information
  g = f;
  g.stamp_s = 0.5;
  EXPECT_FALSE(RepeatsView(view, g, 0.01, 1.0));
}

struct StillRun {
  std::vector<AddResult> results;
  pose_ekf::BufferCounters n;
  double error_m = 0.0, speed_m_s = 0.0;
  double orientation_nees = 0.0, position_nees = 0.0;  // of the final state against the truth
  double max_angle_rad = 0.0;                          // the orientation's largest error after the first 0.5 s
  double gyro_bias_error_rad_s = 0.0;                  // at the end
};

// 1.5 s of a still rig whose tracker returns one noisy frame over and over (rig_sim's static starts: identical
// to 1e-4 px), with the IMU at 100 Hz, in rig_sim's configuration of the filter (bias states, its noise).
StillRun RunStill(double repeat_px, uint32_t seed = 11, double gyro_bias_rad_s = 0.0) {
  EkfConfig c = ConeSimConfig();
  c.estimate_gyro_bias = c.estimate_accel_bias = true;
  c.sigma_q_per_sqrt_s = 5e-5;
  c.sigma_v_m_s_per_sqrt_s = 0.01;
  c.sigma_gyro_rad_s = 0.002;
  c.sigma_accel_m_s2 = 0.05;
  c.cone_repeat_px = repeat_px;
  pose_ekf::MeasurementBuffer b(c);
  const pose_math::Pose T = ConeRigStart();
  std::mt19937 rng(seed);
  EXPECT_EQ(b.AddCamera(Camera(0.0, T, 0.01, 0.05)), AddResult::kInitialized);
  ConeFrame frame = ObserveCones(0.0, T, DefaultCones(), {0, 1, 2}, DefaultIntrinsics(), 1.0, &rng);
  pose_ekf::ImuMeasurement imu = StillImu(T, c);
  imu.omega_camera_rad_s = Eigen::Vector3d::Constant(gyro_bias_rad_s);  // the rig is still: the gyro reads its bias
  StillRun r;
  for (int k = 1; k <= 150; ++k) {
    imu.stamp_s = 0.01 * k - 0.005;
    b.AddImu(imu);
    if (k >= 50) {
      const double dot = std::abs(b.filter().state().x.segment<4>(pose_ekf::kQ).normalized().dot(T.q));
      r.max_angle_rad = std::max(r.max_angle_rad, 2.0 * std::acos(std::min(1.0, dot)));
    }
    if (k % 3 == 0) {
      frame.stamp_s = 0.01 * k;
      r.results.push_back(b.AddCones(frame));
    }
  }
  const pose_ekf::FilterState& s = b.filter().state();
  const Eigen::Vector3d e = s.x.segment<3>(pose_ekf::kP) - T.t;
  r.error_m = e.norm();
  r.speed_m_s = s.x.segment<3>(pose_ekf::kV).norm();
  r.position_nees = e.dot(s.P.block<3, 3>(pose_ekf::kP, pose_ekf::kP).ldlt().solve(e));
  Eigen::Vector4d dq = s.x.segment<4>(pose_ekf::kQ) - T.q;
  if (dq.norm() > 1.0) dq = s.x.segment<4>(pose_ekf::kQ) + T.q;
  const Eigen::Matrix4d Pq = s.P.block<4, 4>(pose_ekf::kQ, pose_ekf::kQ);
  r.orientation_nees = dq.dot(Pq.completeOrthogonalDecomposition().pseudoInverse() * dq);
  r.gyro_bias_error_rad_s = (b.filter().gyro_bias_rad_s() - imu.omega_camera_rad_s).norm();
  r.n = b.counters();
  return r;
}

TEST(ConeRepeat, AStillViewIsFusedOncePerMaxIntervalAndHoldsTheRigStill) {
  const StillRun off = RunStill(0.0);
  const StillRun on = RunStill(0.01);
  ASSERT_EQ(on.results.size(), 50u);
  // Fused at 0.03 s and again at 1.03 s (cone_repeat_max_s 1), every other frame a repeat.
  EXPECT_EQ(on.n.cone_frames_applied, 2u);
  EXPECT_EQ(on.n.cone_frames_repeated, 48u);
  EXPECT_EQ(on.results[0], AddResult::kApplied);
  EXPECT_EQ(on.results[1], AddResult::kRepeated);
  EXPECT_EQ(on.results[34], AddResult::kApplied);
  // A repeat is not a rejection: it does not count toward re-acquisition.
  EXPECT_EQ(on.n.cone_frames_rejected, 0u);
  EXPECT_EQ(on.n.cone_nis_dof, 2u * 3u * pose_ekf::kConeDof);  // the NIS of the fused frames only
  EXPECT_EQ(off.n.cone_frames_applied, 50u);
  EXPECT_EQ(off.n.cone_frames_repeated, 0u);
  // The still camera's updates hold the position where the frames put it, as the fused frames do without the rule.
  EXPECT_LT(on.error_m, 2.0 * off.error_m + 0.002);
  EXPECT_LT(on.speed_m_s, 0.01);
}

// Fused 50 times, one frame's error is believed as if it were 50 independent ones: over 40 seeds the mean NEES of
// the orientation (3 dof) is far above the 95 % interval of a consistent filter's mean, [2.3, 3.8]. Fused once a
// second, with the repeats as a still camera's updates, it is not.
TEST(ConeRepeat, FusingAStillViewOnceKeepsTheFilterHonest) {
  const int seeds = 40;
  double off_q = 0.0, off_p = 0.0, on_q = 0.0, on_p = 0.0;
  for (uint32_t seed = 1; seed <= seeds; ++seed) {
    const StillRun off = RunStill(0.0, seed), on = RunStill(0.01, seed);
    off_q += off.orientation_nees / seeds;
    off_p += off.position_nees / seeds;
    on_q += on.orientation_nees / seeds;
    on_p += on.position_nees / seeds;
  }
  std::printf(
      "[ repeat ] mean NEES over %d seeds, every frame fused: orientation %.2f, position %.2f; "
      "cone_repeat_px 0.01: %.2f, %.2f\n",
      seeds, off_q, off_p, on_q, on_p);
  EXPECT_GT(off_q, 2.0 * 3.8);
  EXPECT_LT(on_q, 3.8);
  EXPECT_GT(off_p, 2.0 * on_p);
}

// The gyro's bias (here 0.3 deg/s per axis, rig_sim's Crista draws 0.4 deg/s per seed) turns the orientation between
// the fused frames, a second apart: the repeats' zero angular rate shows the bias to the gyro update at once, and the
// orientation holds as well as with every frame fused.
TEST(ConeRepeat, AStillViewShowsTheGyroBias) {
  const double bias = 0.3 * M_PI / 180.0;
  const StillRun off = RunStill(0.0, 11, bias), on = RunStill(0.01, 11, bias);
  std::printf(
      "[ repeat ] gyro bias %.4f rad/s: largest orientation error %.4f deg (every frame fused) and %.4f deg "
      "(cone_repeat_px 0.01); bias error at the end %.5f and %.5f rad/s\n",
      bias, off.max_angle_rad * 180.0 / M_PI, on.max_angle_rad * 180.0 / M_PI, off.gyro_bias_error_rad_s,
      on.gyro_bias_error_rad_s);
  EXPECT_LT(on.max_angle_rad, 2.0 * off.max_angle_rad + 1e-4);
  EXPECT_LT(on.gyro_bias_error_rad_s, 0.1 * bias);
}

TEST(ConeRepeat, ConfigRefusesBadValuesByName) {
  EkfConfig c;
  c.cone_repeat_px = -0.1;
  EXPECT_NE(c.Validate().find("cone_repeat_px"), std::string::npos);
  c = EkfConfig();
  c.cone_repeat_max_s = 0.0;
  EXPECT_NE(c.Validate().find("cone_repeat_max_s"), std::string::npos);
  c = EkfConfig();
  c.cone_repeat_sigma_v_m_s = 0.0;
  EXPECT_NE(c.Validate().find("cone_repeat_sigma_v_m_s"), std::string::npos);
  c = EkfConfig();
  c.cone_repeat_sigma_omega_rad_s = -1.0;
  EXPECT_NE(c.Validate().find("cone_repeat_sigma_omega_rad_s"), std::string::npos);
}

}  // namespace
}  // namespace pose_ekf_test
