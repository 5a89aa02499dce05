// The tightly coupled per-cone camera update (cone_measurement.h, cone_update.cpp) and cone frames
// on the synthetic rig: the Jacobian against numeric differences, the gates, one and two visible
// cones, and Monte Carlo NEES. Cone frames in the measurement buffer: test_cone_buffer.cpp; the lone-cone
// ambiguity test: test_cone_ambiguity.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>

#include "pose_ekf/core/cone_measurement.h"
#include "pose_ekf/core/ekf_core.h"
#include "pose_ekf/core/measurement_buffer.h"
#include "pose_ekf/testing/synthetic_cones.h"
#include "pose_math/covariance.h"
#include "pose_math/quaternion.h"
#include "pose_math/rotation.h"

namespace pose_ekf_test {
namespace {

using pose_ekf::AddResult;
using pose_ekf::BufferCounters;
using pose_ekf::ConeFrame;
using pose_ekf::ConeFrameResult;
using pose_ekf::ConeJacobian;
using pose_ekf::ConeVector;
using pose_ekf::EkfConfig;
using pose_ekf::EkfCore;
using pose_ekf::MeasurementBuffer;
using pose_ekf::StateVector;
using pose_ekf::UpdateResult;

void Print(const char* name, const RunStats& s, const BufferCounters& n) {
  std::printf(
      "[ cones ] %-34s rot RMS %.3f deg, pos RMS %.2f mm, mean NEES %.2f, n=%d; cones fused %llu, gated %llu, "
      "joint-dropped %llu, frames rejected %llu, re-init %llu\n",
      name, s.rms_rotation_rad * 180.0 / M_PI, s.rms_position_m * 1e3, s.mean_nees, s.samples,
      static_cast<unsigned long long>(n.cones_applied), static_cast<unsigned long long>(n.cones_gated),
      static_cast<unsigned long long>(n.cones_joint_dropped), static_cast<unsigned long long>(n.cone_frames_rejected),
      static_cast<unsigned long long>(n.reinits));
}

void ExpectJacobianMatches(const StateVector& x, const pose_ekf::ConeGeometry& cone) {
  const pose_ekf::PinholeIntrinsics K = DefaultIntrinsics();
  ConeVector h;
  ConeJacobian H;
  ASSERT_TRUE(pose_ekf::ProjectCone(x, cone, K, &h, &H));
  ASSERT_EQ(H.cols(), x.size());
  ConeJacobian N = ConeJacobian::Zero(pose_ekf::kConeDof, x.size());
  for (int j = 0; j < x.size(); ++j) {
    const double step = 1e-6;
    StateVector a = x, b = x;
    a[j] += step, b[j] -= step;
    ConeVector ha, hb;
    ASSERT_TRUE(pose_ekf::ProjectCone(a, cone, K, &ha, nullptr));
    ASSERT_TRUE(pose_ekf::ProjectCone(b, cone, K, &hb, nullptr));
    N.col(j) = (ha - hb) / (2.0 * step);
  }
  // Pixels per unit quaternion / metre are 1e2-1e3: a relative tolerance on the whole matrix.
  EXPECT_LT((H - N).norm(), 1e-6 * N.norm()) << "analytic\n" << H << "\nnumeric\n" << N;
  EXPECT_GT((H.block<pose_ekf::kConeDof, 3>(0, pose_ekf::kP)).norm(), 1.0);
}

TEST(ConeJacobian, AnalyticMatchesNumericDifferences) {
  const pose_math::Pose T = ConeRigStart();
  const std::vector<pose_ekf::ConeGeometry> cones = DefaultCones();
  for (int n : {pose_ekf::kBaseStates, pose_ekf::kMaxStates}) {
    for (double scale : {1.0, 1.05}) {  // the general rotation (2.36): exact off the unit sphere too
      StateVector x = StateVector::Zero(n);
      for (int i = 0; i < n; ++i) x[i] = 0.1 * std::sin(1.0 + i);  // the other states must not matter
      x.segment<4>(pose_ekf::kQ) = scale * T.q;
      x.segment<3>(pose_ekf::kP) = T.t;
      for (const auto& c : cones) ExpectJacobianMatches(x, c);
    }
  }
  // The model points move with the camera: without that term the position columns would be wrong.
  pose_ekf::ConeGeometry fat = cones[0];
  fat.tau = 0.5;
  StateVector x = StateVector::Zero(pose_ekf::kBaseStates);
  x.segment<4>(pose_ekf::kQ) = T.q;
  x.segment<3>(pose_ekf::kP) = T.t;
  ExpectJacobianMatches(x, fat);
}

TEST(ConeJacobian, ProjectionIsThePinholeOfTheTrackersModelPoints) {
  const pose_math::Pose T = ConeRigStart();
  const pose_ekf::ConeGeometry cone = DefaultCones()[1];
  std::mt19937 rng(1);
  const ConeFrame f = ObserveCones(0.0, T, DefaultCones(), {1}, DefaultIntrinsics(), 0.0, &rng);
  ASSERT_EQ(f.cones.size(), 1u);
  const Eigen::Vector3d peak_c =
      pose_math::RotationFromQuat(T.q).transpose() * (cone.base_m + Eigen::Vector3d(0, 0, cone.height_m) - T.t);
  EXPECT_NEAR(f.cones[0].px[0].x(), 800.0 * peak_c.x() / peak_c.z() + 960.0, 1e-9);
  EXPECT_NEAR(f.cones[0].px[0].y(), 800.0 * peak_c.y() / peak_c.z() + 720.0, 1e-9);
  // A cone behind the camera is not projected.
  StateVector x = StateVector::Zero(pose_ekf::kBaseStates);
  x.segment<4>(pose_ekf::kQ) = pose_math::Multiply(T.q, pose_math::QuatFromRotationVector(Eigen::Vector3d(0, M_PI, 0)));
  x.segment<3>(pose_ekf::kP) = T.t;
  ConeVector h;
  EXPECT_FALSE(pose_ekf::ProjectCone(x, cone, DefaultIntrinsics(), &h, nullptr));
}

TEST(ConeFrameCheck, NamesTheBadField) {
  std::mt19937 rng(1);
  const ConeFrame good = ObserveCones(1.0, ConeRigStart(), DefaultCones(), {0, 1, 2}, DefaultIntrinsics(), 1.0, &rng);
  EXPECT_EQ(pose_ekf::CheckConeFrame(good), "");
  ConeFrame f = good;
  f.cones[1].px[1].x() = NAN;
  EXPECT_EQ(pose_ekf::CheckConeFrame(f), "cones[1].mid_px is not finite");
  f = good;
  f.K.fy_px = 0.0;
  EXPECT_EQ(pose_ekf::CheckConeFrame(f), "fy is not positive and finite");
  f = good;
  f.cones[2].cov_px2[2] = Eigen::Matrix2d::Zero();
  EXPECT_EQ(pose_ekf::CheckConeFrame(f),
            "cones[2].base_cov_px2 is not a finite symmetric positive definite 2x2 matrix");
  // The buffer refuses and counts them.
  MeasurementBuffer b(ConeSimConfig());
  f.cones[2].px[0].y() = INFINITY;
  EXPECT_EQ(b.AddCones(f), AddResult::kRejectedNonFinite);
  EXPECT_EQ(b.counters().nan_rejected, 1u);
}

TEST(ConeGates, SwappedIdsAreGatedAndTheRightConeIsFused) {
  EkfCore ekf = Tight(ConeSimConfig());
  std::mt19937 rng(3);
  ConeFrame f = ObserveCones(0.0, ConeRigStart(), DefaultCones(), {0, 1, 2}, DefaultIntrinsics(), 1.0, &rng);
  std::swap(f.cones[0].cone, f.cones[1].cone);  // the association swapped cones 0 and 1
  std::swap(f.cones[0].cone_id, f.cones[1].cone_id);
  ConeFrameResult r;
  EXPECT_EQ(ekf.UpdateCones(f, &r), UpdateResult::kApplied);
  EXPECT_EQ(r.gated, 2);
  EXPECT_EQ(r.fused, 1);
  EXPECT_GT(r.worst_gate_chi2, 1e4);
  EXPECT_LT((ekf.state().x.segment<3>(pose_ekf::kP) - ConeRigStart().t).norm(), 0.01);
  // All three wrong (the equilateral layout's 120-degree rotation): nothing fused, the state unchanged.
  EkfCore ekf2 = Tight(ConeSimConfig());
  const StateVector before = ekf2.state().x;
  ConeFrame g = ObserveCones(0.0, ConeRigStart(), DefaultCones(), {0, 1, 2}, DefaultIntrinsics(), 1.0, &rng);
  const auto cones = DefaultCones();
  for (int i = 0; i < 3; ++i) g.cones[i].cone = cones[(i + 1) % 3];
  EXPECT_EQ(ekf2.UpdateCones(g, &r), UpdateResult::kGated);
  EXPECT_EQ(r.gated, 3);
  EXPECT_EQ(ekf2.state().x, before);
}

// Each cone just inside its own gate, together far outside chance: the joint check drops cones.
TEST(ConeGates, JointCheckDropsConesThatPassAlone) {
  EkfConfig c = ConeSimConfig();
  EkfCore ekf = Tight(c);
  std::mt19937 rng(4);
  ConeFrame f = ObserveCones(0.0, ConeRigStart(), DefaultCones(), {0, 1, 2}, DefaultIntrinsics(), 0.0, &rng);
  for (auto& o : f.cones)
    for (auto& cov : o.cov_px2) cov = Eigen::Matrix2d::Identity();
  // Peaks moved in different directions (no pose explains them): about 4.6 sigma per cone.
  f.cones[0].px[0] += Eigen::Vector2d(4.6, 0.0);
  f.cones[1].px[0] += Eigen::Vector2d(0.0, -4.6);
  f.cones[2].px[0] += Eigen::Vector2d(-3.3, 3.3);
  ConeFrameResult r;
  EkfCore alone = ekf;
  EkfConfig no_joint = c;
  no_joint.cone_joint_probability = 1.0;
  alone.SetConfig(no_joint);
  EXPECT_EQ(alone.UpdateCones(f, &r), UpdateResult::kApplied);
  EXPECT_EQ(r.gated, 0);
  EXPECT_EQ(r.fused, 3) << "each cone alone passes chi2(4) at 0.9999 (" << ekf.cone_gate_chi2() << ")";
  std::printf("[ cones ] joint NIS of the three: %.1f against chi2(%d) %.1f\n", r.nis, 3 * pose_ekf::kConeDof,
              ekf.cone_joint_chi2(3));
  EXPECT_GT(r.nis, ekf.cone_joint_chi2(3));
  EXPECT_EQ(ekf.UpdateCones(f, &r), UpdateResult::kApplied);
  EXPECT_GE(r.joint_dropped, 1);
  EXPECT_LT(r.fused, 3);
  EXPECT_LE(r.nis, r.joint_threshold);
}

struct Runs {
  RunStats stats;
  BufferCounters n;
  pose_ekf::FilterState final;
};

Runs RunCones(const EkfConfig& c, const std::vector<Event>& events, const ConeRunOptions& o, double warmup_s = 1.0) {
  Runs r;
  r.stats = RunFilterWithCones(c, events, o, warmup_s, &r.n, &r.final);
  return r;
}

TEST(ConeRig, OneConeAtATimeKeepsThePositionBounded) {
  RigSimConfig sim;
  sim.duration_s = 20.0;
  const std::vector<Event> events = GenerateRig(sim);
  ConeRunOptions o;
  o.poses = ConeRunOptions::Poses::kFirstOnly;  // the pose initialises; nothing else but single cones
  o.visible = [](int k, double) { return std::vector<int>{k % 3}; };
  const Runs rotating = RunCones(ConeSimConfig(), events, o);
  o.visible = [](int, double) { return std::vector<int>{1}; };
  const Runs same = RunCones(ConeSimConfig(), events, o);
  o.feed_cones = false;
  const Runs imu_only = RunCones(ConeSimConfig(), events, o);
  Print("one cone per frame, cycling", rotating.stats, rotating.n);
  Print("always the same one cone", same.stats, same.n);
  Print("IMU only after the first pose", imu_only.stats, imu_only.n);
  EXPECT_GT(imu_only.stats.rms_position_m, 1.0);  // drifts away without the camera
  EXPECT_LT(rotating.stats.rms_position_m, 0.02);
  EXPECT_LT(rotating.stats.rms_rotation_rad, 0.5 * M_PI / 180.0);
  EXPECT_LT(same.stats.rms_position_m, 0.05);
  EXPECT_LT(same.stats.rms_position_m, 0.01 * imu_only.stats.rms_position_m);
  EXPECT_GE(rotating.stats.fraction_within_3_sigma, 0.95);
  EXPECT_GT(rotating.n.cones_applied, 550u);
  EXPECT_EQ(rotating.n.reinits, 0u);
}

TEST(ConeRig, TwoConesBeatOne) {
  RigSimConfig sim;
  sim.duration_s = 20.0;
  const std::vector<Event> events = GenerateRig(sim);
  ConeRunOptions o;
  o.poses = ConeRunOptions::Poses::kFirstOnly;
  o.visible = [](int k, double) { return std::vector<int>{k % 3}; };
  const Runs one = RunCones(ConeSimConfig(), events, o);
  o.visible = [](int k, double) { return std::vector<int>{k % 3, (k + 1) % 3}; };
  const Runs two = RunCones(ConeSimConfig(), events, o);
  o.visible = [](int, double) { return std::vector<int>{0, 1, 2}; };
  const Runs three = RunCones(ConeSimConfig(), events, o);
  const RunStats poses = RunFilter(ConeSimConfig(), events, 1.0);
  Print("one cone per frame", one.stats, one.n);
  Print("two cones per frame", two.stats, two.n);
  Print("three cones per frame", three.stats, three.n);
  BufferCounters none;
  Print("camera poses (loosely coupled)", poses, none);
  EXPECT_LT(two.stats.rms_position_m, one.stats.rms_position_m);
  EXPECT_LT(three.stats.rms_position_m, two.stats.rms_position_m);
  EXPECT_LT(two.stats.rms_position_m, 0.01);
  EXPECT_GE(two.stats.fraction_within_3_sigma, 0.95);
}

// Monte Carlo NEES (as test_accuracy's Consistency test) with the camera as per-cone updates only,
// on sample paths of the filter's own process model. Gentler than test_accuracy's (there the camera
// wanders ~20 m and turns ~4 rad in 6 s, which a pose measurement does not mind): the cones must
// stay in the image, so the walk intensities are lower and the runs shorter (about 0.7 m, 0.5 rad).
struct Nees {
  double mean = 0.0, fraction_inside = 0.0, lo = 0.0, hi = 0.0;
};

Nees MonteCarloNees(const char* name, const std::function<std::vector<int>(int, double)>& visible) {
  constexpr int kRuns = 50;
  EkfConfig c = ConeSimConfig();
  c.sigma_omega_rad_s_per_sqrt_s = 0.2;
  c.sigma_a_m_s2_per_sqrt_s = 0.1;
  const double dt = 0.01;  // the continuous white-noise-jerk model over one IMU step (test_accuracy)
  c.sigma_q_per_sqrt_s = c.sigma_omega_rad_s_per_sqrt_s * dt / std::sqrt(12.0);
  c.sigma_v_m_s_per_sqrt_s = c.sigma_a_m_s2_per_sqrt_s * dt / std::sqrt(3.0);
  c.sigma_p_m_per_sqrt_s = c.sigma_a_m_s2_per_sqrt_s * dt * dt / std::sqrt(20.0);
  c.accel_gate_m_s2 = 0.0;
  std::vector<double> sum_nees;
  double total = 0.0;
  int count = 0;
  uint64_t fused = 0, gated = 0, dropped = 0;
  for (int run = 0; run < kRuns; ++run) {
    RigSimConfig sim;
    sim.motion = RigSimConfig::Motion::kProcessModel;
    sim.duration_s = 4.0;
    sim.seed = 100 + run;
    sim.omega_walk_rad_s_per_sqrt_s = c.sigma_omega_rad_s_per_sqrt_s;
    sim.accel_walk_m_s2_per_sqrt_s = c.sigma_a_m_s2_per_sqrt_s;
    ConeRunOptions o;
    o.seed = 200 + run;
    o.poses = ConeRunOptions::Poses::kFirstOnly;
    o.visible = visible;
    const Runs r = RunCones(c, GenerateRig(sim), o);
    if (sum_nees.empty()) sum_nees.assign(r.stats.nees.size(), 0.0);
    EXPECT_EQ(r.stats.nees.size(), sum_nees.size());
    for (size_t k = 0; k < std::min(sum_nees.size(), r.stats.nees.size()); ++k) sum_nees[k] += r.stats.nees[k];
    total += r.stats.mean_nees * r.stats.samples;
    count += r.stats.samples;
    fused += r.n.cones_applied, gated += r.n.cones_gated, dropped += r.n.cones_joint_dropped;
  }
  Nees n;
  n.lo = ChiSquareQuantile(6.0 * kRuns, 0.025) / kRuns, n.hi = ChiSquareQuantile(6.0 * kRuns, 0.975) / kRuns;
  int inside = 0;
  for (double sum : sum_nees) inside += sum / kRuns >= n.lo && sum / kRuns <= n.hi;
  n.fraction_inside = static_cast<double>(inside) / sum_nees.size();
  n.mean = total / count;
  std::printf(
      "[ cones ] NEES over %d runs, %s: mean %.2f (6 expected), %.1f %% of steps in [%.2f, %.2f]; cones fused %llu, "
      "gated %llu, joint-dropped %llu\n",
      kRuns, name, n.mean, 100.0 * n.fraction_inside, n.lo, n.hi, static_cast<unsigned long long>(fused),
      static_cast<unsigned long long>(gated), static_cast<unsigned long long>(dropped));
  return n;
}

TEST(ConeConsistency, AverageNeesInsideTheChiSquareInterval) {
  const Nees three = MonteCarloNees("three cones", [](int, double) { return std::vector<int>{0, 1, 2}; });
  EXPECT_GT(three.mean, three.lo);
  EXPECT_LT(three.mean, three.hi);
  // 92 % of the steps with the mid fused as a third point, 90 % with the peak and base alone (less
  // information per frame, so the NEES follows the motion more along the sequence).
  EXPECT_GE(three.fraction_inside, 0.85);
  // Every other frame a single cone (heading then comes from the gyro): the mean holds, the NEES
  // varies more along the sequence (about 77 % of the steps inside).
  const Nees alternating = MonteCarloNees("one and three cones alternating", [](int k, double) {
    return k % 2 ? std::vector<int>{0, 1, 2} : std::vector<int>{k % 3};
  });
  EXPECT_GT(alternating.mean, alternating.lo);
  EXPECT_LT(alternating.mean, alternating.hi);
  EXPECT_GE(alternating.fraction_inside, 0.75);
}

}  // namespace
}  // namespace pose_ekf_test
