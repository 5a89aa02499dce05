// pose_ekf on the simulated rig (rig_sim, issue 6): Monte Carlo NEES
// consistency on handheld motion with the Crista model, the look-away outage
// with gyros on and off, and the RMS figures for the note.
//
// The events reuse the synthetic rig's Event (so RunFilter scores them), but
// the motion, the IMU samples and the truth come from rig_sim: its analytic
// trajectory, and its IMU model with bias, noise, quantisation, the mounting
// rotation and the lever arm. The camera pose is rig_sim's truth perturbed by
// a known covariance, as cone_tracker would report it.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "pose_ekf/node/node_config.h"
#include "pose_ekf/testing/synthetic_rig.h"
#include "pose_math/covariance.h"
#include "pose_math/rotation.h"
#include "rig_sim/camera_model.h"
#include "rig_sim/scenario.h"

namespace pose_ekf_test {
namespace {

constexpr double kDegToRad = M_PI / 180.0;
constexpr double kRadToDeg = 180.0 / M_PI;

rig_sim::Scenario MakeSim(const std::string& name, uint64_t seed, double duration_s) {
  rig_sim::Scenario s;
  std::string error;
  if (!rig_sim::MakeScenario(name, seed, RIG_MODEL_LAYOUTS_DIR, &s, &error)) throw std::runtime_error(error);
  rig_sim::ShortenScenario(duration_s, 1.0, &s);
  return s;
}

// A cone_tracker pose of the thesis's cones at 2-3 m (ROS order x y z rx ry rz,
// cones frame): a few mm, ~0.1 deg, with depth-like correlations between the
// lateral position and the rotation that moves the image the same way.
pose_math::Matrix6d CameraCovarianceRos() {
  Eigen::Matrix<double, 6, 1> sigma;
  sigma << 0.003, 0.003, 0.004, 0.1 * kDegToRad, 0.1 * kDegToRad, 0.08 * kDegToRad;
  pose_math::Matrix6d corr = pose_math::Matrix6d::Identity();
  corr(0, 4) = corr(4, 0) = 0.3;
  corr(1, 3) = corr(3, 1) = -0.3;
  return sigma.asDiagonal() * corr * sigma.asDiagonal();
}

// Every cone's middle inside the image, less than 60 deg off the axis (beyond
// that the distortion polynomial folds back and Project means nothing).
bool ConesInView(const rig_sim::Scenario& s, const rig_model::CameraModel& camera, const rig_sim::TruePose& pose) {
  for (const rig_sim::ConeSpec& cone : s.scene.cones) {
    const Eigen::Vector3d p = pose.R_cones_camera.transpose() * (cone.mid_m() - pose.p_camera_in_cones_m);
    Eigen::Vector2d uv;
    if (p.z() < p.norm() * std::cos(60.0 * kDegToRad) || !camera.Project(p, &uv)) return false;
    if (uv.x() < 0.0 || uv.y() < 0.0 || uv.x() >= s.camera.model.width_px || uv.y() >= s.camera.model.height_px)
      return false;
  }
  return true;
}

Truth TruthAt(const rig_sim::Trajectory& trajectory, double t_s) {
  const rig_sim::TruePose p = trajectory.At(t_s);
  Truth truth;
  truth.T_cones_camera.q = pose_math::QuatFromRotation(p.R_cones_camera);
  truth.T_cones_camera.t = p.p_camera_in_cones_m;
  truth.omega_camera_rad_s = trajectory.OmegaCamera(t_s);
  return truth;
}

// Camera at 30 Hz while the cones are in view, IMU at 100 Hz rotated into
// camera_optical (pose_ekf takes IMU samples in {C}: the adapter applies the
// tf camera_optical <- imu, here ImuConfig::R_camera_imu(), the same way).
// pose_ekf reads an IMU sample as the rates at its stamp, while rig_sim's
// sample stamped t covers (t - dt, t] (mean rate; specific force at the
// midpoint), so the samples are stamped at the midpoint t - dt/2. Stamped at
// t they would lag 5 ms, which doubles the orientation error after fast pans.
std::vector<Event> Generate(const rig_sim::Scenario& s, uint64_t noise_seed, const pose_math::Matrix6d& cov6) {
  const double imu_stamp_offset_s = -0.5 / s.imu.rate_hz;
  const rig_sim::Trajectory trajectory(s.trajectory);
  rig_sim::ImuSimulator imu(s.imu, trajectory);
  const rig_model::CameraModel& camera = s.camera.model;
  const Eigen::Matrix3d R_camera_imu = s.imu.R_camera_imu();
  const Eigen::Matrix<double, 6, 6> L = cov6.llt().matrixL();
  std::mt19937_64 rng(noise_seed);
  std::normal_distribution<double> normal;
  std::vector<Event> events;
  int64_t frame = 0;
  for (;;) {
    const rig_sim::ImuSample sample = imu.Next();
    if (sample.stamp_s > s.trajectory.duration_s) break;
    const double imu_stamp_s = sample.stamp_s + imu_stamp_offset_s;
    for (double t = frame / s.camera.rate_hz; t <= imu_stamp_s; t = ++frame / s.camera.rate_hz) {
      if (!ConesInView(s, camera, trajectory.At(t))) continue;
      Event e;
      e.stamp_s = t;
      e.is_camera = true;
      e.truth = TruthAt(trajectory, t);
      Eigen::Matrix<double, 6, 1> n;
      for (int i = 0; i < 6; ++i) n[i] = normal(rng);
      const Eigen::Matrix<double, 6, 1> d = L * n;  // on the tangent plane: left (fixed-axis) rotation, as ROS
      e.camera.stamp_s = t;
      e.camera.T_cones_camera.q =
          pose_math::Multiply(pose_math::QuatFromRotationVector(d.tail<3>()), e.truth.T_cones_camera.q);
      e.camera.T_cones_camera.t = e.truth.T_cones_camera.t + d.head<3>();
      e.camera.cov = pose_math::CovarianceThesisFromRos(e.camera.T_cones_camera.q, cov6);
      events.push_back(e);
    }
    Event e;
    e.stamp_s = imu_stamp_s;
    e.truth = TruthAt(trajectory, e.stamp_s);
    e.imu.stamp_s = e.stamp_s;
    e.imu.omega_camera_rad_s = R_camera_imu * sample.omega_imu_rad_s;
    e.imu.accel_camera_m_s2 = R_camera_imu * sample.accel_imu_m_s2;
    e.imu.p_imu_in_camera_m = s.imu.p_imu_in_camera_m;  // the lever arm, from the same tf
    events.push_back(e);
  }
  return events;
}

// The filter as configured for the rig (tuned here, defaults unchanged):
// - the Crista's turn-on gyro bias (0.4 deg/s per axis) is estimated (3.2.1);
// - σ_gyro = 0.003 rad/s, the Crista's 0.12 deg/s white noise plus its
//   quantisation, instead of the default 0.01;
// - σ_ω = 1 rad/s/√s and σ_q = 3e-4/√s instead of 3 and 1e-3: with the
//   defaults the camera hardly constrains ω, so the bias converges slowly,
//   the look-away error exceeds 1 deg, and the NEES is too low (4.7 for 6 DOF,
//   conservative). These values give a mean NEES inside the 95 % interval.
pose_ekf::EkfConfig RigConfig(const rig_sim::Scenario& s) {
  pose_ekf::EkfConfig c;
  c.gravity_m_s2 = s.imu.gravity_m_s2;
  c.estimate_gyro_bias = true;
  c.init_sigma_gyro_bias_rad_s = s.imu.gyro_bias_sigma_deg_s * kDegToRad;
  c.sigma_gyro_rad_s = 0.003;
  c.sigma_omega_rad_s_per_sqrt_s = 1.0;
  c.sigma_q_per_sqrt_s = 3e-4;
  return c;
}

// The filter as rig_sim's bags and sim.launch run it: ar_bringup/config/pose_ekf_rig_sim.yaml itself (its IMU model:
// centred gyro samples, ω's walk at the samples, both bias states, the Crista's noise; pose_ekf's README, "The gyro
// bias"), fed this test's camera poses instead of cone observations, with the scenario's gravity.
pose_ekf::EkfConfig ShippedRigConfig(const rig_sim::Scenario& s) {
  pose_ekf::EkfConfig c =
      pose_ekf::LoadConfigFile(std::string(POSE_EKF_SOURCE_DIR) + "/../ar_bringup/config/pose_ekf_rig_sim.yaml").ekf;
  c.camera_update = pose_ekf::CameraUpdate::kPose;
  c.gravity_m_s2 = s.imu.gravity_m_s2;
  return c;
}

struct Accumulated {
  std::vector<double> sum_nees;  // per evaluated IMU step, over the runs
  double sum_rot2 = 0.0, sum_pos2 = 0.0;
  int samples = 0;
  uint64_t camera_gated = 0, reinits = 0;
};

// Bar-Shalom's NEES test over kRuns handheld sequences (different seeds, so
// different paths, IMU biases and noise). The pose error is 6-DOF (x y z rx ry
// rz, ROS form) and its covariance the filter's 7x7 mapped by
// pose_math::CovarianceRosFromThesis, so N runs' NEES sum is chi2(6 N) for a
// consistent filter; the 95 % interval of the run average is
// [chi2_0.025(6N), chi2_0.975(6N)] / N (Boost.Math quantiles). Steps: the
// filter right after every IMU sample from kWarmupS on (the first second
// starts from the loose initial sigmas of ω, v, a and the bias).
void ExpectAverageNeesInsideTheChiSquareInterval(pose_ekf::EkfConfig (*config)(const rig_sim::Scenario&),
                                                 const char* name) {
  constexpr int kRuns = 50;
  constexpr double kDurationS = 12.0, kWarmupS = 1.0;
  Accumulated acc;
  for (int run = 0; run < kRuns; ++run) {
    const rig_sim::Scenario s = MakeSim("handheld", 1000 + run, kDurationS);
    const std::vector<Event> events = Generate(s, 7000 + run, CameraCovarianceRos());
    const RunStats r = RunFilter(config(s), events, kWarmupS);
    if (acc.sum_nees.empty()) acc.sum_nees.assign(r.nees.size(), 0.0);
    ASSERT_EQ(r.nees.size(), acc.sum_nees.size()) << "run " << run;
    for (size_t k = 0; k < r.nees.size(); ++k) acc.sum_nees[k] += r.nees[k];
    acc.sum_rot2 += r.rms_rotation_rad * r.rms_rotation_rad * r.samples;
    acc.sum_pos2 += r.rms_position_m * r.rms_position_m * r.samples;
    acc.samples += r.samples;
    acc.camera_gated += r.camera_gated;
    acc.reinits += r.reinits;
  }
  const double lo = ChiSquareQuantile(6.0 * kRuns, 0.025) / kRuns, hi = ChiSquareQuantile(6.0 * kRuns, 0.975) / kRuns;
  double total = 0.0;
  int inside = 0;
  for (double sum : acc.sum_nees) {
    total += sum / kRuns;
    inside += sum / kRuns >= lo && sum / kRuns <= hi;
  }
  const double mean = total / acc.sum_nees.size();
  const double fraction = static_cast<double>(inside) / acc.sum_nees.size();
  std::cout << "[ rig_sim ] " << name << ": NEES, " << kRuns << " handheld runs of " << kDurationS << " s: mean "
            << mean << " (6 DOF), 95% interval [" << lo << ", " << hi << "], " << 100.0 * fraction << " % of "
            << acc.sum_nees.size() << " steps inside\n";
  std::cout << "[ rig_sim ] " << name << ": cones visible (handheld, " << kRuns << " runs): orientation RMS "
            << std::sqrt(acc.sum_rot2 / acc.samples) * kRadToDeg << " deg, position RMS "
            << std::sqrt(acc.sum_pos2 / acc.samples) * 1e3 << " mm; camera poses gated " << acc.camera_gated
            << ", re-initialisations " << acc.reinits << "\n";
  EXPECT_GT(mean, lo);
  EXPECT_LT(mean, hi);
  // Per step the run average is not held to the interval: it varies along the
  // sequence (still start, then motion), and only about half of the steps fall
  // inside (printed above).
}

TEST(RigSim, AverageNeesInsideTheChiSquareInterval) {
  ExpectAverageNeesInsideTheChiSquareInterval(RigConfig, "point-sample gyro");
}

// The same test for the configuration rig_sim's bags are replayed with.
TEST(RigSim, ShippedConfigurationAverageNeesInsideTheChiSquareInterval) {
  ExpectAverageNeesInsideTheChiSquareInterval(ShippedRigConfig, "pose_ekf_rig_sim.yaml's IMU model");
}

struct Outage {
  double start_s = 0.0, end_s = 0.0;  // the longest stretch without camera frames
};

Outage LongestCameraGap(const std::vector<Event>& events) {
  Outage o;
  double last = 0.0;
  for (const Event& e : events) {
    if (!e.is_camera) continue;
    if (e.stamp_s - last > o.end_s - o.start_s) o = {last, e.stamp_s};
    last = e.stamp_s;
  }
  return o;
}

// The gyro experiment of 7.3 on rig_sim's look_away scenario: the camera pans
// away from the cones (frames only while every cone is in the image) and back.
// Gyros on, a handheld turn (70 deg, 2 s ramps, peak ~65 deg/s; 4-5 s out of
// view): the orientation error stays <= 1 deg throughout. rig_sim's own
// look_away (110 deg at up to 170 deg/s, ~7.6 s out of view) is printed and
// held to 3 deg: the filter predicts with the last gyro sample (5.19), a
// zero-order hold that lags the truth by about dt/2 x the change of rate.
TEST(RigSim, LookAwayWithGyrosKeepsTheOrientation) {
  for (int fast = 0; fast < 2; ++fast) {
    for (uint64_t seed = 1; seed <= 5; ++seed) {
      rig_sim::Scenario s = MakeSim("look_away", seed, fast ? 20.0 : 14.0);
      ASSERT_EQ(s.trajectory.segments.size(), 2u);
      rig_sim::Segment& turn = s.trajectory.segments[1];
      ASSERT_EQ(turn.kind, rig_sim::SegmentKind::kLookAway);
      if (!fast) {
        turn.duration_s = 6.0;
        turn.ramp_s = 2.0;
        turn.amplitude_deg = 70.0;
      }
      const std::vector<Event> events = Generate(s, 100 + seed, CameraCovarianceRos());
      const Outage o = LongestCameraGap(events);
      ASSERT_GE(o.end_s - o.start_s, 2.0) << "seed " << seed;
      const auto in_outage = [&](double t) { return t > o.start_s && t < o.end_s; };
      const auto visible = [&](double t) { return t < o.start_s || t > o.end_s + 1.0; };
      const RunStats out = RunFilter(RigConfig(s), events, 1.0, in_outage);
      const RunStats vis = RunFilter(RigConfig(s), events, 1.0, visible);
      std::cout << "[ rig_sim ] look_away " << (fast ? "110 deg" : "70 deg") << " seed " << seed
                << ": cones visible: orientation RMS " << vis.rms_rotation_rad * kRadToDeg << " deg, position RMS "
                << vis.rms_position_m * 1e3 << " mm; cones out of view " << o.end_s - o.start_s
                << " s, gyros on: orientation RMS " << out.rms_rotation_rad * kRadToDeg << " deg (max "
                << out.max_rotation_rad * kRadToDeg << "), position RMS " << out.rms_position_m * 1e3
                << " mm; camera poses gated " << out.camera_gated << ", re-initialisations " << out.reinits << "\n";
      EXPECT_LE(out.max_rotation_rad * kRadToDeg, fast ? 3.0 : 1.0) << "seed " << seed;
      EXPECT_LT(vis.rms_rotation_rad * kRadToDeg, 0.15) << "seed " << seed;
      EXPECT_GT(out.samples, 190) << "seed " << seed;
    }
  }
}

// Gyros (and accelerometer) off: nothing moves the estimate while the cones are
// out of view, so the pose freezes, as the thesis's users saw (7.3); the
// truth meanwhile pans far away.
TEST(RigSim, LookAwayWithoutGyrosFreezesThePose) {
  const rig_sim::Scenario s = MakeSim("look_away", 1, 20.0);
  const std::vector<Event> events = Generate(s, 101, CameraCovarianceRos());
  const Outage o = LongestCameraGap(events);
  ASSERT_GE(o.end_s - o.start_s, 2.0);
  pose_ekf::EkfConfig c = RigConfig(s);
  c.use_gyro = false;
  c.accel_mode = pose_ekf::AccelMode::kOff;
  pose_ekf::MeasurementBuffer b(c);
  pose_math::Pose frozen;
  double max_change = 0.0, max_error = 0.0;
  for (const Event& e : events) {
    e.is_camera ? b.AddCamera(e.camera) : b.AddImu(e.imu);
    if (e.is_camera && e.stamp_s <= o.start_s) frozen = b.filter().Pose().pose;
    if (e.is_camera || e.stamp_s <= o.start_s || e.stamp_s >= o.end_s) continue;
    const pose_math::Pose now = b.filter().Pose().pose;
    max_change =
        std::max(max_change, pose_math::RotationErrorRad(frozen, now) + pose_math::TranslationError(frozen, now));
    max_error = std::max(max_error, pose_math::RotationErrorRad(e.truth.T_cones_camera, now));
  }
  std::cout << "[ rig_sim ] look_away seed 1, gyros off: pose change over the " << o.end_s - o.start_s << " s outage "
            << max_change << ", max orientation error " << max_error * kRadToDeg << " deg\n";
  EXPECT_LT(max_change, 1e-12);
  EXPECT_GT(max_error * kRadToDeg, 30.0);
}

}  // namespace
}  // namespace pose_ekf_test
