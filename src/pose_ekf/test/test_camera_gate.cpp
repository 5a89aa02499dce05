// The chi-square gate on camera poses (EkfConfig::camera_gate_chi2) and
// the re-initialisation after reinit_after_rejections gated poses in a row:
// the statistic itself on the core, then wrong poses fed to a tracking filter
// through the measurement buffer on the synthetic rig.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "pose_ekf/core/ekf_core.h"
#include "pose_ekf/core/measurement_buffer.h"
#include "pose_ekf/testing/synthetic_rig.h"
#include "pose_math/covariance.h"
#include "pose_math/rotation.h"

namespace pose_ekf_test {
namespace {

using pose_ekf::AddResult;
using pose_ekf::CameraMeasurement;
using pose_ekf::EkfConfig;
using pose_ekf::EkfCore;
using pose_ekf::MeasurementBuffer;
using pose_ekf::UpdateResult;

// A filter initialised from SomePose with sigma 0.01 rad / 0.01 m, no time passed:
// S is then P + R = 2 R on the pose, so the statistic is known in closed form.
EkfCore Initialised(const EkfConfig& c) {
  EkfCore ekf{c};
  EXPECT_TRUE(ekf.Initialize(Camera(0.0, SomePose(), 0.01, 0.01)));
  return ekf;
}

TEST(CameraGate, ThresholdIsTheParameterAndZeroTurnsItOff) {
  EkfConfig c;
  EXPECT_DOUBLE_EQ(EkfCore{c}.camera_gate_chi2(), 1000.0);
  EXPECT_GT(1000.0, ChiSquareQuantile(6, 1.0 - 1e-12));  // far beyond chance for a consistent filter
  c.camera_gate_chi2 = 16.8;
  EXPECT_DOUBLE_EQ(EkfCore{c}.camera_gate_chi2(), 16.8);
  c.camera_gate_chi2 = 0.0;
  EXPECT_TRUE(std::isinf(EkfCore{c}.camera_gate_chi2()));
}

// The statistic is the Mahalanobis distance on the pose's 6 dof: a position
// offset d along x gives d² / (2 σ²), and a rotation offset θ gives θ² / (2 σ²)
// as well, whatever its size, because the quaternion rows are taken on the
// tangent plane (along q the 7-dof form would add (θ²/8)² / 1e-10).
TEST(CameraGate, StatisticIsTheSixDofMahalanobisDistance) {
  const double var = 2.0 * 0.01 * 0.01;
  for (double d : {0.005, 0.02, 0.05}) {
    EkfCore ekf = Initialised(EkfConfig{});
    pose_math::Pose z = SomePose();
    z.t.x() += d;
    double chi2 = -1.0;
    ekf.UpdateCamera(Camera(0.0, z, 0.01, 0.01), nullptr, &chi2);
    EXPECT_NEAR(chi2, d * d / var, 1e-6 * d * d / var) << d;
  }
  for (double theta : {0.005, 0.02, 0.05}) {
    EkfCore ekf = Initialised(EkfConfig{});
    pose_math::Pose z = SomePose();
    z.q = pose_math::Multiply(pose_math::QuatFromRotationVector(Eigen::Vector3d(0.0, theta, 0.0)), z.q);
    double chi2 = -1.0, nis = -1.0;
    ekf.UpdateCamera(Camera(0.0, z, 0.01, 0.01), &nis, &chi2);
    // Only first order in θ: R lives on the tangent plane of z, P on that of the prediction.
    EXPECT_NEAR(chi2, theta * theta / var, 0.02 * theta * theta / var) << theta;
  }
}

TEST(CameraGate, MirroredQuaternionGivesTheSameStatistic) {
  pose_math::Pose z = SomePose();
  z.q = pose_math::Multiply(pose_math::QuatFromRotationVector(Eigen::Vector3d(0.02, 0.0, 0.01)), z.q);
  z.t.y() += 0.02;
  CameraMeasurement m = Camera(0.0, z, 0.01, 0.01), mirrored = m;
  mirrored.T_cones_camera.q = -m.T_cones_camera.q;
  double a = -1.0, b = -2.0;
  Initialised(EkfConfig{}).UpdateCamera(m, nullptr, &a);
  Initialised(EkfConfig{}).UpdateCamera(mirrored, nullptr, &b);
  EXPECT_NEAR(a, b, 1e-9 * a);
}

TEST(CameraGate, RejectsAPoseFiveMetresOffAndLeavesTheStateAlone) {
  EkfCore ekf = Initialised(EkfConfig{});
  ekf.Predict(0.1);
  const pose_ekf::FilterState before = ekf.state();
  pose_math::Pose z = SomePose();
  z.t.x() -= 5.0;
  double chi2 = 0.0;
  EXPECT_EQ(ekf.UpdateCamera(Camera(0.1, z, 0.01, 0.01), nullptr, &chi2), UpdateResult::kGated);
  EXPECT_GT(chi2, 1e3);  // the initial sigma of v (0.5 m/s) has spread the position over 0.1 s
  EXPECT_EQ(ekf.state().x, before.x);
  EXPECT_EQ(ekf.state().P, before.P);
  // A rotation alone (0.8 rad) is gated too: the tangent component of the
  // quaternion innovation is sin(0.4), so chi2 ≈ (2 sin 0.4)² / 2σ² (R lies on
  // the tangent plane at z, P on that at the prediction: 8 % apart here).
  EkfCore fresh = Initialised(EkfConfig{});
  z = SomePose();
  z.q = pose_math::Multiply(pose_math::QuatFromRotationVector(Eigen::Vector3d(0.0, 0.0, 0.8)), z.q);
  EXPECT_EQ(fresh.UpdateCamera(Camera(0.0, z, 0.01, 0.01), nullptr, &chi2), UpdateResult::kGated);
  EXPECT_NEAR(chi2, std::pow(2.0 * std::sin(0.4), 2) / (2.0 * 0.01 * 0.01), 300.0);
}

TEST(CameraGate, OffFusesAnything) {
  EkfConfig c;
  c.camera_gate_chi2 = 0.0;
  EkfCore ekf = Initialised(c);
  pose_math::Pose z = SomePose();
  z.t.x() -= 5.0;
  EXPECT_EQ(ekf.UpdateCamera(Camera(0.0, z, 0.01, 0.01)), UpdateResult::kApplied);
  EXPECT_LT(ekf.Pose().pose.t.x(), SomePose().t.x() - 2.0);
}

TEST(CameraGate, InvalidParametersAreNamed) {
  EkfConfig c;
  c.camera_gate_chi2 = -1.0;
  c.reinit_after_rejections = -1;
  const std::string err = c.Validate();
  EXPECT_NE(err.find("camera_gate_chi2"), std::string::npos) << err;
  EXPECT_NE(err.find("reinit_after_rejections"), std::string::npos) << err;
  c.camera_gate_chi2 = std::nan("");
  c.reinit_after_rejections = 0;
  EXPECT_NE(c.Validate().find("camera_gate_chi2"), std::string::npos);
}

// --- Through the measurement buffer, on the synthetic rig ---

struct GateRun {
  MeasurementBuffer buffer{EkfConfig{}};
  double max_position_error_m = 0.0;  // against the truth, after each IMU sample past 1 s
  std::vector<AddResult> camera_results;
};

// Feeds the rig's events; camera frames with stamps in [bad_from_s, bad_to_s)
// are replaced by `corrupt(truthful pose)`. The position error is measured
// against truth + `truth_offset`, after each IMU sample from score_from_s on.
void Feed(GateRun& run, const std::vector<Event>& events, double bad_from_s, double bad_to_s,
          const std::function<void(pose_math::Pose&)>& corrupt, double score_from_s = 1.0,
          const Eigen::Vector3d& truth_offset = Eigen::Vector3d::Zero()) {
  for (const Event& e : events) {
    if (e.is_camera) {
      CameraMeasurement m = e.camera;
      if (e.stamp_s >= bad_from_s && e.stamp_s < bad_to_s) corrupt(m.T_cones_camera);
      run.camera_results.push_back(run.buffer.AddCamera(m));
      continue;
    }
    run.buffer.AddImu(e.imu);
    if (e.stamp_s < score_from_s) continue;
    const Eigen::Vector3d truth = e.truth.T_cones_camera.t + truth_offset;
    run.max_position_error_m = std::max(run.max_position_error_m, (run.buffer.filter().Pose().pose.t - truth).norm());
  }
}

RigSimConfig Sim() {
  RigSimConfig sim;
  sim.duration_s = 6.0;
  return sim;
}

constexpr double kFrameS = 1.0 / 30.0;

// Camera frames stamped in [from_s, to_s).
std::ptrdiff_t CameraFrames(const std::vector<Event>& events, double from_s, double to_s) {
  return std::count_if(events.begin(), events.end(),
                       [&](const Event& e) { return e.is_camera && e.stamp_s >= from_s && e.stamp_s < to_s; });
}

// The case: ten wrong poses (here 5 m off, and a quaternion scaled by
// 3 with a 40 deg error) into a tracking filter. None is fused, each is counted.
TEST(CameraGate, WrongPosesIntoATrackingFilterAreNotFusedAndCounted) {
  const std::vector<Event> events = GenerateRig(Sim());
  GateRun clean;
  Feed(clean, events, 0, 0, [](pose_math::Pose&) {});
  ASSERT_EQ(clean.buffer.counters().camera_gated, 0u);
  const double from = 3.0 + 0.5 * kFrameS, to = from + 10 * kFrameS;
  ASSERT_EQ(CameraFrames(events, from, to), 10);

  GateRun shifted;
  Feed(shifted, events, from, to, [](pose_math::Pose& T) { T.t.x() -= 5.0; });
  EXPECT_EQ(shifted.buffer.counters().camera_gated, 10u);
  EXPECT_EQ(shifted.buffer.counters().reinits, 0u);
  EXPECT_EQ(std::count(shifted.camera_results.begin(), shifted.camera_results.end(), AddResult::kGated), 10);
  EXPECT_GT(shifted.buffer.counters().camera_gate_last_rejected_chi2, 1e4);
  EXPECT_EQ(shifted.buffer.counters().camera_applied, clean.buffer.counters().camera_applied - 10);
  EXPECT_LT(shifted.max_position_error_m, 0.02) << "clean run: " << clean.max_position_error_m;

  GateRun rotated;
  Feed(rotated, events, from, to, [](pose_math::Pose& T) {
    T.q = 3.0 * pose_math::Multiply(pose_math::QuatFromRotationVector(Eigen::Vector3d(0.7, 0.0, 0.0)), T.q);
  });
  EXPECT_EQ(rotated.buffer.counters().camera_gated, 10u);
  EXPECT_LT(rotated.max_position_error_m, 0.02);
  EXPECT_LT(pose_math::RotationErrorRad(rotated.buffer.filter().Pose().pose, clean.buffer.filter().Pose().pose),
            0.2 * M_PI / 180);
}

// reinit_after_rejections poses in a row: the camera was right (here the cones
// were moved 5 m at t = 3 s, so every later pose is 5 m off the filter). The
// filter re-initialises once, from the 15th, and follows the new poses.
TEST(CameraGate, RejectionsInARowReinitialiseAndTheFilterFollows) {
  const std::vector<Event> events = GenerateRig(Sim());
  const double jump_s = 3.0 + 0.5 * kFrameS;
  const Eigen::Vector3d jump(-5.0, 0.0, 0.0);
  GateRun run;
  ASSERT_EQ(run.buffer.filter().config().reinit_after_rejections, 15);
  // Scored against the moved truth from 0.5 s after the re-initialisation.
  Feed(
      run, events, jump_s, 1e9, [&](pose_math::Pose& T) { T.t += jump; }, jump_s + 15 * kFrameS + 0.5, jump);
  EXPECT_EQ(run.buffer.counters().reinits, 1u);
  EXPECT_EQ(run.buffer.counters().camera_gated, 15u);
  const auto first_jumped = run.camera_results.begin() + CameraFrames(events, 0.0, jump_s);
  EXPECT_EQ(std::count(run.camera_results.begin(), first_jumped, AddResult::kGated), 0);
  EXPECT_EQ(std::count(first_jumped, first_jumped + 14, AddResult::kGated), 14);
  EXPECT_EQ(first_jumped[14], AddResult::kReinitialized);
  EXPECT_EQ(std::count(first_jumped + 15, run.camera_results.end(), AddResult::kApplied),
            run.camera_results.end() - first_jumped - 15);
  EXPECT_EQ(run.buffer.camera_gated_in_a_row(), 0);
  EXPECT_LT(run.max_position_error_m, 0.02);
}

// The re-initialisation restarts the pose, not the gyro: the bias learned so far is kept.
TEST(CameraGate, ReinitialisationKeepsTheGyroBias) {
  EkfConfig config;
  config.estimate_gyro_bias = true;
  config.reinit_after_rejections = 3;
  MeasurementBuffer buffer(config);
  ASSERT_EQ(buffer.AddCamera(Camera(0.0, SomePose())), AddResult::kInitialized);
  pose_ekf::FilterState learned = buffer.filter().state();
  ASSERT_GT(learned.x.size(), pose_ekf::kBaseStates);
  learned.x.segment<3>(pose_ekf::kB) = Eigen::Vector3d(0.01, -0.02, 0.005);
  learned.P.block<3, 3>(pose_ekf::kB, pose_ekf::kB) = 1e-8 * Eigen::Matrix3d::Identity();
  const_cast<EkfCore&>(buffer.filter()).Restore(learned);
  pose_math::Pose moved = SomePose();
  moved.t.x() -= 5.0;
  EXPECT_EQ(buffer.AddCamera(Camera(0.01, moved)), AddResult::kGated);
  EXPECT_EQ(buffer.AddCamera(Camera(0.02, moved)), AddResult::kGated);
  EXPECT_EQ(buffer.AddCamera(Camera(0.03, moved)), AddResult::kReinitialized);
  EXPECT_LT((buffer.filter().Pose().pose.t - moved.t).norm(), 1e-9);
  EXPECT_TRUE(buffer.filter().gyro_bias_rad_s().isApprox(Eigen::Vector3d(0.01, -0.02, 0.005), 1e-12));
  // The learned variance (grown only by 0.03 s of random walk), not the initial 0.02^2 rad^2/s^2.
  EXPECT_LT(buffer.filter().state().P(pose_ekf::kB, pose_ekf::kB), 1e-7);
}

TEST(CameraGate, RejectionsNotInARowOrWithReinitOffDoNotReinitialise) {
  const std::vector<Event> events = GenerateRig(Sim());
  // Every other frame wrong for 2 s: 30 rejections, never two in a row.
  GateRun alternating;
  int k = 0;
  ASSERT_EQ(CameraFrames(events, 2.0 + 0.5 * kFrameS, 4.0 + 0.5 * kFrameS), 60);
  Feed(alternating, events, 2.0 + 0.5 * kFrameS, 4.0 + 0.5 * kFrameS, [&](pose_math::Pose& T) {
    if (k++ % 2 == 0) T.t.z() += 5.0;
  });
  EXPECT_EQ(alternating.buffer.counters().camera_gated, 30u);
  EXPECT_EQ(alternating.buffer.counters().reinits, 0u);
  EXPECT_LT(alternating.max_position_error_m, 0.02);

  EkfConfig off;
  off.reinit_after_rejections = 0;
  GateRun never;
  never.buffer.SetConfig(off);
  // 1 s of wrong poses: on the IMU alone the position spreads, and after about
  // 2.4 s a 5 m offset would fit inside the gate.
  const double from = 3.0 + 0.5 * kFrameS, to = from + 30 * kFrameS;
  Feed(never, events, from, to, [](pose_math::Pose& T) { T.t.x() -= 5.0; });
  EXPECT_EQ(never.buffer.counters().reinits, 0u);
  EXPECT_EQ(never.buffer.counters().camera_gated, 30u);
  EXPECT_LT(never.max_position_error_m, 0.05);
}

}  // namespace
}  // namespace pose_ekf_test
