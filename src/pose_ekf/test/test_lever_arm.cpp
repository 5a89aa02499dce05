// The camera-IMU lever arm in the accelerometer model, the accelerometer bias
// states and the damped motion model: Jacobians against central differences,
// and what each buys on the synthetic rig.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "pose_ekf/core/ekf_core.h"
#include "pose_ekf/core/process_model.h"
#include "pose_ekf/testing/synthetic_rig.h"
#include "state_jacobian.h"

namespace pose_ekf {
namespace {

struct Layout {
  bool gyro_bias, accel_bias;
};

class LeverArmJacobian : public ::testing::TestWithParam<Layout> {};

TEST_P(LeverArmJacobian, AccelModelMatchesNumeric) {
  EkfConfig c;
  c.estimate_gyro_bias = GetParam().gyro_bias;
  c.estimate_accel_bias = GetParam().accel_bias;
  const int n = StateSize(c), ba = AccelBiasIndex(c);
  const Eigen::Vector3d r(0.02, 0.08, -0.06);  // rig_sim's mount
  for (AccelMode mode : {AccelMode::kOrientation, AccelMode::kPositionAndOrientation}) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
      const StateVector x = RandomState(n, seed, 4.0);
      const Eigen::MatrixXd H = AccelJacobian(x, 9.81, mode, r, ba);
      const Eigen::MatrixXd Hn = NumericJacobian(
          [&](const StateVector& s) { return Eigen::VectorXd(AccelModel(s, 9.81, mode, r, ba)); }, x, 3);
      EXPECT_LT((H - Hn).cwiseAbs().maxCoeff(), 1e-7) << "seed " << seed << "\nH\n" << H << "\nnumeric\n" << Hn;
      // The lever-arm term itself, so a Jacobian that ignored it would fail: ω×(ω×r) moves h.
      EXPECT_GT((AccelModel(x, 9.81, mode, r, ba) - AccelModel(x, 9.81, mode, Eigen::Vector3d::Zero(), ba)).norm(),
                1e-3);
    }
  }
}

TEST_P(LeverArmJacobian, DampedTransitionMatchesNumeric) {
  EkfConfig c;
  c.estimate_gyro_bias = GetParam().gyro_bias;
  c.estimate_accel_bias = GetParam().accel_bias;
  const int n = StateSize(c);
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const StateVector x = RandomState(n, seed, 4.0);
    const Eigen::MatrixXd F = TransitionJacobian(x, 0.02, QuatIntegration::kFirstOrder, 0.5, 0.2);
    const Eigen::MatrixXd Fn = NumericJacobian(
        [&](const StateVector& s) {
          return Eigen::VectorXd(PropagateState(s, 0.02, QuatIntegration::kFirstOrder, 0.5, 0.2));
        },
        x, n);
    EXPECT_LT((F - Fn).cwiseAbs().maxCoeff(), 1e-8) << "seed " << seed;
  }
  const StateMatrix Q = ProcessNoise(c, n, 0.01);
  if (c.estimate_accel_bias) {
    EXPECT_DOUBLE_EQ(Q(AccelBiasIndex(c), AccelBiasIndex(c)), 0.01 * 1e-6);
  }
}

INSTANTIATE_TEST_SUITE_P(Layouts, LeverArmJacobian,
                         ::testing::Values(Layout{false, false}, Layout{true, false}, Layout{false, true},
                                           Layout{true, true}));

TEST(LeverArm, NoiseCoversAlphaCrossR) {
  const Eigen::Vector3d r(0.0, 0.1, 0.0);
  const Eigen::Matrix3d N = AccelLeverArmNoise(r, 10.0);
  // α×r is perpendicular to r: no variance along r, (σ|r|)² across it.
  EXPECT_NEAR(r.normalized().dot(N * r.normalized()), 0.0, 1e-15);
  EXPECT_NEAR(N(0, 0), 1.0, 1e-12);
  EXPECT_NEAR(N(2, 2), 1.0, 1e-12);
}

// Damped velocity: with no measurement at all the position stays within v τ of where it was.
TEST(MotionModel, DampedVelocityBoundsThePosition) {
  EkfConfig c;
  c.velocity_time_constant_s = 0.5;
  c.accel_time_constant_s = 0.2;
  StateVector x = StateVector::Zero(kBaseStates);
  x[kQ] = 1.0;
  x.segment<3>(kV) = Eigen::Vector3d(1.0, 0.0, 0.0);
  x.segment<3>(kA) = Eigen::Vector3d(2.0, 0.0, 0.0);
  for (int i = 0; i < 1000; ++i) x = PropagateState(x, 0.01, QuatIntegration::kFirstOrder, 0.5, 0.2);
  // ∫ v = v0 τv + a0 τa τv (to first order): 0.5 + 0.2 = 0.7 m; undamped it would be 110 m.
  EXPECT_NEAR(x[kP], 0.7, 0.05);
  EXPECT_LT(x.segment<3>(kV).norm(), 1e-6);
}

}  // namespace
}  // namespace pose_ekf

namespace pose_ekf_test {
namespace {

// The synthetic rig's IMU moved to r from the camera: the specific force gains
// ω×(ω×r) + α×r (α by a central difference of the true rate between IMU samples).
std::vector<Event> WithLeverArm(std::vector<Event> events, const Eigen::Vector3d& r) {
  std::vector<size_t> imu;
  for (size_t i = 0; i < events.size(); ++i)
    if (!events[i].is_camera) imu.push_back(i);
  for (size_t k = 1; k + 1 < imu.size(); ++k) {
    Event& e = events[imu[k]];
    const Event &prev = events[imu[k - 1]], &next = events[imu[k + 1]];
    const Eigen::Vector3d w = e.truth.omega_camera_rad_s;
    const Eigen::Vector3d alpha =
        (next.truth.omega_camera_rad_s - prev.truth.omega_camera_rad_s) / (next.stamp_s - prev.stamp_s);
    e.imu.accel_camera_m_s2 += w.cross(w.cross(r)) + alpha.cross(r);
    e.imu.p_imu_in_camera_m = r;
  }
  return events;
}

// A fast-turning handheld rig (3x the synthetic sinusoid: up to ~2 rad/s, ~6 rad/s²)
// with a 10 cm lever arm and a 1.5 s camera outage: with the lever arm modelled
// the position and orientation errors in the outage are lower than without.
TEST(LeverArm, ModelledLeverArmBeatsIgnoringItOnARotatingRig) {
  double pos_on = 0.0, pos_off = 0.0, rot_on = 0.0, rot_off = 0.0;
  for (uint32_t seed = 1; seed <= 4; ++seed) {
    RigSimConfig rig;
    rig.duration_s = 8.0;
    rig.seed = seed;
    rig.motion_scale = 3.0;
    rig.outage_start_s = 5.0;
    rig.outage_end_s = 6.5;
    const std::vector<Event> events = WithLeverArm(GenerateRig(rig), Eigen::Vector3d(0.02, 0.08, -0.06));
    pose_ekf::EkfConfig c;
    c.accel_gate_m_s2 = 0.0;  // the motion is well above the gate; (5.39) models it
    const auto in_outage = [&](double t) { return t >= rig.outage_start_s && t < rig.outage_end_s; };
    const RunStats on = RunFilter(c, events, 1.0, in_outage);
    pose_ekf::EkfConfig noise_only = c;  // α×r as noise only (α not estimated)
    noise_only.alpha_from_gyro = false;
    noise_only.sigma_angular_accel_rad_s2 = 10.0;
    const RunStats alpha_noise = RunFilter(noise_only, events, 1.0, in_outage);
    c.model_lever_arm = false;
    const RunStats off = RunFilter(c, events, 1.0, in_outage);
    std::printf(
        "[ lever ] seed %u outage: position RMS %.1f mm modelled, %.1f mm with alpha x r as noise, %.1f mm "
        "ignored; orientation %.3f, %.3f, %.3f deg\n",
        seed, on.rms_position_m * 1e3, alpha_noise.rms_position_m * 1e3, off.rms_position_m * 1e3,
        on.rms_rotation_rad * 180 / M_PI, alpha_noise.rms_rotation_rad * 180 / M_PI, off.rms_rotation_rad * 180 / M_PI);
    pos_on += on.rms_position_m;
    pos_off += off.rms_position_m;
    rot_on += on.rms_rotation_rad;
    rot_off += off.rms_rotation_rad;
  }
  EXPECT_LT(pos_on, 0.8 * pos_off);
  EXPECT_LT(rot_on, rot_off);
}

// A constant accelerometer bias (camera axes) is learned while the cones are in view.
TEST(AccelBias, ConvergesOnTheSyntheticRig) {
  const Eigen::Vector3d bias(0.15, -0.1, 0.2);
  RigSimConfig rig;
  rig.duration_s = 30.0;
  rig.seed = 3;
  rig.motion_scale = 2.0;
  std::vector<Event> events = GenerateRig(rig);
  for (Event& e : events) e.imu.accel_camera_m_s2 += bias;
  pose_ekf::EkfConfig c;
  c.accel_gate_m_s2 = 0.0;
  c.estimate_accel_bias = true;
  pose_ekf::MeasurementBuffer b(c);
  double err_at_5s = -1.0;
  for (const Event& e : events) {
    e.is_camera ? b.AddCamera(e.camera) : b.AddImu(e.imu);
    if (err_at_5s < 0.0 && e.stamp_s >= 5.0) err_at_5s = (b.filter().accel_bias_m_s2() - bias).norm();
  }
  const Eigen::Vector3d est = b.filter().accel_bias_m_s2();
  const double sigma = std::sqrt(
      b.filter().state().P.block<3, 3>(pose_ekf::AccelBiasIndex(c), pose_ekf::AccelBiasIndex(c)).trace() / 3.0);
  std::printf(
      "[ accel bias ] estimate [%.4f %.4f %.4f] (true [%.2f %.2f %.2f]), error %.4f at 5 s, %.4f at 30 s, "
      "sigma %.4f\n",
      est.x(), est.y(), est.z(), bias.x(), bias.y(), bias.z(), err_at_5s, (est - bias).norm(), sigma);
  EXPECT_LT((est - bias).norm(), 0.03);
  EXPECT_LT((est - bias).norm(), err_at_5s);
  // Without the states the same run estimates no bias at all.
  c.estimate_accel_bias = false;
  pose_ekf::EkfCore plain(c);
  EXPECT_EQ(plain.accel_bias_m_s2(), Eigen::Vector3d::Zero());
}

// omega_walk_at_gyro: ω's random walk added at the gyro samples, not spread over the predictions between them,
// leaves q no random walk beyond the gyro's noise, so the camera pins the gyro bias down sooner (config.h).
TEST(GyroBias, OmegaWalkAtGyroSamplesLearnsTheBiasSooner) {
  pose_ekf::EkfConfig c;
  c.estimate_gyro_bias = true;
  c.gyro_is_centred_interval_mean = true;
  c.accel_gate_m_s2 = 0.0;
  RigSimConfig rig;
  rig.duration_s = 6.0;
  rig.gyro_bias_rad_s = Eigen::Vector3d(0.004, -0.003, 0.005);
  double err_spread = 0.0, err_at_gyro = 0.0;
  for (rig.seed = 1; rig.seed <= 8; ++rig.seed) {
    const std::vector<Event> events = GenerateRig(rig);
    double err[2], sigma[2];
    for (const bool at_gyro : {false, true}) {
      c.omega_walk_at_gyro = at_gyro;
      pose_ekf::MeasurementBuffer b(c);
      for (const Event& e : events) e.is_camera ? b.AddCamera(e.camera) : b.AddImu(e.imu);
      err[at_gyro] = (b.filter().gyro_bias_rad_s() - rig.gyro_bias_rad_s).norm();
      sigma[at_gyro] = std::sqrt(b.filter().state().P.block<3, 3>(pose_ekf::kB, pose_ekf::kB).trace() / 3.0);
    }
    std::printf(
        "[ gyro bias ] seed %u after %.0f s: error %.5f rad/s, sigma %.5f (walk spread); error %.5f, sigma "
        "%.5f (at the gyro samples)\n",
        rig.seed, rig.duration_s, err[0], sigma[0], err[1], sigma[1]);
    EXPECT_LT(sigma[1], 0.5 * sigma[0]);
    EXPECT_LT(err[1], 3.0 * std::sqrt(3.0) * sigma[1]);  // the smaller sigma is honest
    err_spread += err[0];
    err_at_gyro += err[1];
  }
  EXPECT_LT(err_at_gyro, 0.8 * err_spread);
}
}  // namespace
}  // namespace pose_ekf_test
