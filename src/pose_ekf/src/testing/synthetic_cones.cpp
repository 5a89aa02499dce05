#include "pose_ekf/testing/synthetic_cones.h"

#include <cmath>
#include <deque>
#include <stdexcept>

#include "pose_math/covariance.h"
#include "pose_math/rotation.h"
#include "rig_model/layout.h"

namespace pose_ekf_test {
namespace {

pose_ekf::StateVector StateAt(const pose_math::Pose& T) {
  pose_ekf::StateVector x = pose_ekf::StateVector::Zero(pose_ekf::kBaseStates);
  x.segment<4>(pose_ekf::kQ) = T.q;
  x.segment<3>(pose_ekf::kP) = T.t;
  return x;
}

// A message waiting to reach the buffer (options.delay_s after its stamp).
struct Pending {
  double arrival_s = 0.0;
  bool is_cones = false;
  pose_ekf::CameraMeasurement pose;
  pose_ekf::ConeFrame cones;
};

}  // namespace

std::vector<pose_ekf::ConeGeometry> DefaultCones() { return pose_ekf::ConeGeometries(rig_model::DefaultLayout()); }

pose_ekf::PinholeIntrinsics DefaultIntrinsics() { return {800.0, 800.0, 960.0, 720.0}; }

pose_ekf::ConeFrame ObserveCones(double stamp_s, const pose_math::Pose& T,
                                 const std::vector<pose_ekf::ConeGeometry>& layout, const std::vector<int>& cones,
                                 const pose_ekf::PinholeIntrinsics& K, double sigma_px, std::mt19937* rng) {
  pose_ekf::ConeFrame f;
  f.stamp_s = stamp_s;
  f.K = K;
  f.layout = layout;  // as the adapter sets it: the lone-cone ambiguity test sees every layout cone
  std::normal_distribution<double> noise(0.0, sigma_px);
  const pose_ekf::StateVector x = StateAt(T);
  for (int id : cones) {
    pose_ekf::ConeObservation o;
    o.cone_id = id;
    o.cone = layout[static_cast<size_t>(id)];
    pose_ekf::ConeVector h;
    const auto X = rig_model::CorrectedModelPoints(o.cone.base_m, o.cone.height_m, o.cone.tau, T.t);
    bool in_front = true;
    for (const Eigen::Vector3d& p : X) in_front &= (pose_math::RotationFromQuat(T.q).transpose() * (p - T.t)).z() > 0.3;
    if (!in_front || !pose_ekf::ProjectCone(x, o.cone, K, &h, nullptr)) continue;
    bool in_image = true;  // the image is 2 cx by 2 cy pixels
    for (int j = 0; j < pose_ekf::kConeDof / 2; ++j) {
      in_image &= h[2 * j] >= 0.0 && h[2 * j] <= 2.0 * K.cx_px && h[2 * j + 1] >= 0.0 && h[2 * j + 1] <= 2.0 * K.cy_px;
    }
    if (!in_image) continue;
    for (size_t j = 0; j < pose_ekf::kConeMeasuredPoints.size(); ++j) {
      const int k = pose_ekf::kConeMeasuredPoints[j];
      const double du = noise(*rng), dv = noise(*rng);
      o.px[k] = h.segment<2>(2 * static_cast<int>(j)) + Eigen::Vector2d(du, dv);
    }
    o.px[1] = 0.5 * (o.px[0] + o.px[2]);  // the mid, as the tracker sets it
    for (Eigen::Matrix2d& c : o.cov_px2) c = sigma_px * sigma_px * Eigen::Matrix2d::Identity();
    f.cones.push_back(o);
  }
  return f;
}

RunStats RunFilterWithCones(const pose_ekf::EkfConfig& config, const std::vector<Event>& events,
                            const ConeRunOptions& o, double warmup_s, pose_ekf::BufferCounters* counters_out,
                            pose_ekf::FilterState* final_out) {
  pose_ekf::MeasurementBuffer buffer(config);
  std::mt19937 rng(o.seed);
  std::deque<Pending> pending;  // in arrival order (constant delay)
  double sum_rot2 = 0.0, sum_pos2 = 0.0, sum_nees = 0.0;
  int within = 0, frame = 0;
  bool first_pose = true;
  RunStats s;
  auto deliver = [&](double now) {
    while (!pending.empty() && pending.front().arrival_s <= now) {
      const Pending& p = pending.front();
      p.is_cones ? buffer.AddCones(p.cones) : buffer.AddCamera(p.pose);
      pending.pop_front();
    }
  };
  for (const Event& e : events) {
    deliver(e.stamp_s);
    if (e.is_camera) {
      const std::vector<int> visible = o.visible ? o.visible(frame, e.stamp_s) : std::vector<int>{};
      ++frame;
      const pose_ekf::ConeFrame f =
          ObserveCones(e.stamp_s, e.truth.T_cones_camera, o.layout, visible, o.K, o.sigma_px, &rng);
      const bool send_pose = o.poses == ConeRunOptions::Poses::kAll ||
                             (o.poses == ConeRunOptions::Poses::kFirstOnly && first_pose) ||
                             (o.poses == ConeRunOptions::Poses::kWhenThreeCones && f.cones.size() >= 3);
      if (send_pose) {
        first_pose = false;
        pending.push_back({e.stamp_s + o.delay_s, false, e.camera, {}});
      }
      if (o.feed_cones && !f.cones.empty()) pending.push_back({e.stamp_s + o.delay_s, true, {}, f});
      deliver(e.stamp_s);
      continue;
    }
    buffer.AddImu(e.imu);
    if (!buffer.filter().initialized() || e.stamp_s < warmup_s) continue;
    const pose_math::PoseWithCovariance est = buffer.filter().Pose();
    const Eigen::Matrix<double, 6, 1> err = PoseError(e.truth.T_cones_camera, est.pose);
    sum_rot2 += err.tail<3>().squaredNorm();
    sum_pos2 += err.head<3>().squaredNorm();
    s.max_rotation_rad = std::max(s.max_rotation_rad, err.tail<3>().norm());
    const pose_math::Matrix6d cov6 = pose_math::CovarianceRosFromThesis(est.pose.q, est.cov);
    for (int i = 0; i < 6; ++i) within += std::abs(err[i]) <= 3.0 * std::sqrt(cov6(i, i));
    s.nees.push_back(err.dot(cov6.ldlt().solve(err)));
    sum_nees += s.nees.back();
    ++s.samples;
  }
  if (s.samples > 0) {
    s.rms_rotation_rad = std::sqrt(sum_rot2 / s.samples);
    s.rms_position_m = std::sqrt(sum_pos2 / s.samples);
    s.fraction_within_3_sigma = within / (6.0 * s.samples);
    s.mean_nees = sum_nees / s.samples;
  }
  deliver(1e300);  // what is still on its way
  if (final_out) *final_out = buffer.filter().state();
  s.camera_gated = buffer.counters().camera_gated;
  s.reinits = buffer.counters().reinits;
  if (counters_out) *counters_out = buffer.counters();
  return s;
}

pose_ekf::EkfConfig ConeSimConfig() {
  pose_ekf::EkfConfig c;
  c.camera_update = pose_ekf::CameraUpdate::kCones;
  c.sigma_gyro_rad_s = 0.01;
  c.sigma_accel_m_s2 = 0.1;
  return c;
}

pose_math::Pose ConeRigStart() {
  RigSimConfig sim;
  sim.duration_s = 0.0;
  return GenerateRig(sim).front().truth.T_cones_camera;
}

pose_ekf::ImuMeasurement StillImu(const pose_math::Pose& T, const pose_ekf::EkfConfig& c) {
  pose_ekf::ImuMeasurement imu;
  imu.accel_camera_m_s2 = pose_math::RotationFromQuat(T.q).transpose() * Eigen::Vector3d(0, 0, c.gravity_m_s2);
  return imu;
}

pose_ekf::EkfCore Tight(const pose_ekf::EkfConfig& c, double sigma_p_m) {
  pose_ekf::EkfCore ekf{c};
  if (!ekf.Initialize(Camera(0.0, ConeRigStart(), 0.001, 0.001)))
    throw std::runtime_error("Tight: the filter refused its initial camera pose");
  if (sigma_p_m > 0.0) {
    pose_ekf::FilterState s = ekf.state();
    s.P.block<3, 3>(pose_ekf::kP, pose_ekf::kP) = sigma_p_m * sigma_p_m * Eigen::Matrix3d::Identity();
    ekf.Restore(s);
  }
  return ekf;
}

}  // namespace pose_ekf_test
