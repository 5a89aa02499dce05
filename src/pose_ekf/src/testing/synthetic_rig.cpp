#include "pose_ekf/testing/synthetic_rig.h"

#include <cmath>
#include <random>

#include "pose_math/covariance.h"
#include "pose_math/rotation.h"

namespace pose_ekf_test {
namespace {

using pose_math::Quat;

// Integer ticks of 1/3000 s so 30 Hz and 100 Hz stamps are exact multiples.
constexpr int kTicksPerS = 3000, kCameraTicks = 100, kImuTicks = 30;

// Camera 2.5 m from the cones, 1.2 m up, looking at the origin (z forward, y down).
pose_math::Pose StartPose() {
  const Eigen::Vector3d p(0.3, -2.5, 1.2);
  const Eigen::Vector3d z = (-p).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  Eigen::Matrix3d R;
  R << x, z.cross(x), z;
  return {pose_math::QuatFromRotation(R), p};
}

Truth SinusoidTruth(double t, double scale) {
  const pose_math::Pose start = StartPose();
  const Eigen::Vector3d amp_p = scale * Eigen::Vector3d(0.25, 0.15, 0.1), w_p(2.1, 2.9, 1.7), ph_p(0.3, 1.1, 2.0);
  const Eigen::Vector3d amp_r = scale * Eigen::Vector3d(0.25, 0.2, 0.15), w_r(2.5, 1.9, 3.1), ph_r(0.7, 0.2, 1.4);
  auto orientation = [&](double s) {
    const Eigen::Vector3d r =
        amp_r.cwiseProduct((w_r * s + ph_r).array().sin().matrix()) - amp_r.cwiseProduct(ph_r.array().sin().matrix());
    return pose_math::Multiply(start.q, pose_math::QuatFromRotationVector(r));
  };
  Truth tr;
  tr.T_cones_camera.q = orientation(t);
  tr.T_cones_camera.t = start.t + amp_p.cwiseProduct((w_p * t + ph_p).array().sin().matrix());
  tr.v_cones_m_s = amp_p.cwiseProduct(w_p).cwiseProduct((w_p * t + ph_p).array().cos().matrix());
  tr.a_cones_m_s2 = -amp_p.cwiseProduct(w_p.cwiseAbs2()).cwiseProduct((w_p * t + ph_p).array().sin().matrix());
  // Body rate from q̇ = ½ q ⊗ [0 ω] by a central difference (error ~1e-10 rad/s).
  const double h = 1e-6;
  const Quat q_dot = (orientation(t + h) - orientation(t - h)) / (2.0 * h);
  tr.omega_camera_rad_s = 2.0 * pose_math::Multiply(pose_math::Conjugate(tr.T_cones_camera.q), q_dot).tail<3>();
  return tr;
}

Eigen::Vector3d Gaussian3(std::mt19937& rng, double sigma) {
  std::normal_distribution<double> n(0.0, sigma);
  const double x = n(rng), y = n(rng), z = n(rng);
  return {x, y, z};
}

void AddCamera(const RigSimConfig& c, std::mt19937& rng, Event* e) {
  e->camera.stamp_s = e->stamp_s;
  const Eigen::Vector3d dtheta = Gaussian3(rng, c.camera_sigma_rad);
  const Eigen::Vector3d dp = Gaussian3(rng, c.camera_sigma_m);
  e->camera.T_cones_camera.q =
      pose_math::Multiply(pose_math::QuatFromRotationVector(dtheta), e->truth.T_cones_camera.q);
  e->camera.T_cones_camera.t = e->truth.T_cones_camera.t + dp;
  pose_math::Matrix6d cov6 = pose_math::Matrix6d::Zero();
  cov6.diagonal() << Eigen::Vector3d::Constant(c.camera_sigma_m * c.camera_sigma_m),
      Eigen::Vector3d::Constant(c.camera_sigma_rad * c.camera_sigma_rad);
  e->camera.cov = pose_math::CovarianceThesisFromRos(e->camera.T_cones_camera.q, cov6);
}

void AddImu(const RigSimConfig& c, std::mt19937& rng, Event* e) {
  e->imu.stamp_s = e->stamp_s;
  e->imu.omega_camera_rad_s = e->truth.omega_camera_rad_s + c.gyro_bias_rad_s + Gaussian3(rng, c.gyro_sigma_rad_s);
  const Eigen::Matrix3d R = pose_math::RotationFromQuat(e->truth.T_cones_camera.q);
  e->imu.accel_camera_m_s2 = R.transpose() * (e->truth.a_cones_m_s2 + Eigen::Vector3d(0.0, 0.0, c.gravity_m_s2)) +
                             Gaussian3(rng, c.accel_sigma_m_s2);  // (5.30)
}

}  // namespace

std::vector<Event> GenerateRig(const RigSimConfig& c) {
  std::mt19937 rng(c.seed);
  std::mt19937 walk_rng(c.seed ^ 0x9e3779b9u);  // separate stream: truth does not depend on sensor draws
  const int end_tick = static_cast<int>(std::lround(c.duration_s * kTicksPerS));
  const double dt = 1.0 / kTicksPerS;
  Truth walk;  // kProcessModel state, integrated with the exact quaternion update (2.71)
  walk.T_cones_camera = StartPose();
  std::vector<Event> events;
  for (int tick = 0; tick <= end_tick; ++tick) {
    const double t = tick * dt;
    const Truth truth = c.motion == RigSimConfig::Motion::kSinusoid ? SinusoidTruth(t, c.motion_scale) : walk;
    const bool in_outage = t >= c.outage_start_s && t < c.outage_end_s;
    if (tick % kCameraTicks == 0 && !in_outage) {
      Event e;
      e.stamp_s = t;
      e.is_camera = true;
      e.truth = truth;
      AddCamera(c, rng, &e);
      events.push_back(e);
    }
    if (tick % kImuTicks == 0) {
      Event e;
      e.stamp_s = t;
      e.truth = truth;
      AddImu(c, rng, &e);
      events.push_back(e);
    }
    if (c.motion == RigSimConfig::Motion::kProcessModel) {
      walk.T_cones_camera.q = pose_math::IntegrateExact(walk.T_cones_camera.q, walk.omega_camera_rad_s, dt);
      walk.T_cones_camera.t += dt * walk.v_cones_m_s + 0.5 * dt * dt * walk.a_cones_m_s2;
      walk.v_cones_m_s += dt * walk.a_cones_m_s2;
      walk.omega_camera_rad_s += Gaussian3(walk_rng, c.omega_walk_rad_s_per_sqrt_s * std::sqrt(dt));
      walk.a_cones_m_s2 += Gaussian3(walk_rng, c.accel_walk_m_s2_per_sqrt_s * std::sqrt(dt));
    }
  }
  return events;
}

Eigen::Matrix<double, 6, 1> PoseError(const pose_math::Pose& truth, const pose_math::Pose& estimate) {
  Eigen::Matrix<double, 6, 1> e;
  const Quat dq = pose_math::Multiply(truth.q, pose_math::Conjugate(estimate.q.normalized()));
  e << truth.t - estimate.t, pose_math::RotationVectorFromQuat(dq);
  return e;
}

double Nees(const pose_math::Pose& truth, const pose_math::PoseWithCovariance& estimate) {
  const Eigen::Matrix<double, 6, 1> e = PoseError(truth, estimate.pose);
  const pose_math::Matrix6d cov6 = pose_math::CovarianceRosFromThesis(estimate.pose.q, estimate.cov);
  return e.dot(cov6.ldlt().solve(e));
}

pose_ekf::CameraMeasurement Camera(double t, const pose_math::Pose& T, double sigma_rad, double sigma_m) {
  pose_ekf::CameraMeasurement m;
  m.stamp_s = t;
  m.T_cones_camera = T;
  pose_math::Matrix6d cov6 = pose_math::Matrix6d::Zero();
  cov6.diagonal() << Eigen::Vector3d::Constant(sigma_m * sigma_m), Eigen::Vector3d::Constant(sigma_rad * sigma_rad);
  m.cov = pose_math::CovarianceThesisFromRos(T.q, cov6);
  return m;
}

pose_math::Pose SomePose() {
  return {pose_math::QuatFromRotationVector(Eigen::Vector3d(0.3, -0.2, 1.0)), Eigen::Vector3d(0.5, -2.0, 1.2)};
}

}  // namespace pose_ekf_test
