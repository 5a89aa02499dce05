#include "imu_track.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cone_survey {

Eigen::Matrix3d ExpSo3(const Eigen::Vector3d& w) {
  const double a = w.norm();
  if (a < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(a, w / a).toRotationMatrix();
}

GyroIntegrator::GyroIntegrator(const std::vector<ImuReading>& imu, const Eigen::Matrix3d& R_camera_imu)
    : imu_(imu), R_camera_imu_(R_camera_imu) {
  std::vector<double> dt;
  for (size_t i = 1; i < imu.size(); ++i) dt.push_back(imu[i].stamp_s - imu[i - 1].stamp_s);
  if (!dt.empty()) {
    std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
    if (dt[dt.size() / 2] > 0.0) period_s_ = dt[dt.size() / 2];
  }
}

Eigen::Matrix3d GyroIntegrator::Delta(double t_a, double t_b, const Eigen::Vector3d& bias_imu) const {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  if (t_b <= t_a || imu_.empty()) return R;
  const double half = 0.5 * period_s_;
  // First sample whose interval ends after t_a.
  auto it = std::lower_bound(imu_.begin(), imu_.end(), t_a - half,
                             [](const ImuReading& r, double t) { return r.stamp_s < t; });
  for (; it != imu_.end() && it->stamp_s - half < t_b; ++it) {
    const double overlap = std::min(t_b, it->stamp_s + half) - std::max(t_a, it->stamp_s - half);
    if (overlap > 0.0) R = R * ExpSo3(R_camera_imu_ * (it->gyro_rad_s - bias_imu) * overlap);  // (2.71)
  }
  return R;
}

Eigen::Vector3d GyroIntegrator::SpecificForceIntegral(double t_a, double t_b, double t_ref,
                                                      const Eigen::Matrix3d& R_world_camera_ref,
                                                      const Eigen::Vector3d& bias_imu) const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  const double half = 0.5 * period_s_;
  auto it = std::lower_bound(imu_.begin(), imu_.end(), t_a - half,
                             [](const ImuReading& r, double t) { return r.stamp_s < t; });
  for (; it != imu_.end() && it->stamp_s - half < t_b; ++it) {
    const double overlap = std::min(t_b, it->stamp_s + half) - std::max(t_a, it->stamp_s - half);
    if (overlap <= 0.0) continue;
    const double t = it->stamp_s;
    const Eigen::Matrix3d R = t >= t_ref ? Eigen::Matrix3d(R_world_camera_ref * Delta(t_ref, t, bias_imu))
                                         : Eigen::Matrix3d(R_world_camera_ref * Delta(t, t_ref, bias_imu).transpose());
    sum += R * (R_camera_imu_ * it->accel_m_s2) * overlap;
  }
  return sum;
}

bool GyroIntegrator::UpInCamera(double t, double half_window, Eigen::Vector3d* up) const {
  auto it = std::lower_bound(imu_.begin(), imu_.end(), t - half_window,
                             [](const ImuReading& r, double s) { return r.stamp_s < s; });
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (; it != imu_.end() && it->stamp_s <= t + half_window; ++it, ++n) sum += it->accel_m_s2;
  if (n == 0 || sum.norm() < 1e-9) return false;
  *up = (R_camera_imu_ * sum).normalized();
  return true;
}

bool GyroIntegrator::StillStartBias(double still_s, Eigen::Vector3d* bias_imu) const {
  if (imu_.empty()) return false;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sq = Eigen::Vector3d::Zero();
  int n = 0;
  bool level_force = true;
  for (const ImuReading& r : imu_) {
    if (r.stamp_s > imu_.front().stamp_s + still_s) break;
    sum += r.gyro_rad_s;
    sq += r.gyro_rad_s.cwiseAbs2();
    level_force = level_force && std::abs(r.accel_m_s2.norm() - 9.81) < 0.3;
    ++n;
  }
  if (n < 10 || !level_force) return false;
  const Eigen::Vector3d mean = sum / n;
  const Eigen::Vector3d spread = (sq / n - mean.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt();
  if (spread.maxCoeff() > 0.02) return false;
  *bias_imu = mean;
  return true;
}

std::vector<Track> TrackCones(const SurveyInput& in, const GyroIntegrator& gyro, const Eigen::Vector3d& bias_imu,
                              const SurveyConfig& config) {
  const rig_model::CameraModel& cam = in.camera;
  Eigen::Matrix3d K;
  K << cam.fx_px, 0, cam.cx_px, 0, cam.fy_px, cam.cy_px, 0, 0, 1;
  const Eigen::Matrix3d K_inv = K.inverse();
  auto carry = [&](const Eigen::Matrix3d& H, const Eigen::Vector2d& p) {
    const Eigen::Vector3d q = H * p.homogeneous();
    return Eigen::Vector2d(q.head<2>() / q.z());
  };
  std::vector<Track> done, open;
  for (int f = 0; f < static_cast<int>(in.frames.size()); ++f) {
    const SurveyFrame& frame = in.frames[f];
    // Close tracks missing for too long.
    for (size_t i = 0; i < open.size();) {
      if (f - open[i].sightings.back().first > config.track_max_gap_frames) {
        done.push_back(open[i]);
        open.erase(open.begin() + i);
      } else {
        ++i;
      }
    }
    // Costs of every (track, sighting) pair within the gate.
    struct Pair {
      double cost;
      int track, sighting;
    };
    std::vector<Pair> pairs;
    for (int t = 0; t < static_cast<int>(open.size()); ++t) {
      const auto [lf, ls] = open[t].sightings.back();
      const ConeSighting& last = in.frames[lf].cones[ls];
      // A point's bearing d in the last frame is R^T d in this one.
      const Eigen::Matrix3d H = K * gyro.Delta(in.frames[lf].stamp_s, frame.stamp_s, bias_imu).transpose() * K_inv;
      const Eigen::Vector2d peak = carry(H, last.peak_px), base = carry(H, last.base_px);
      const double gate = config.track_gate_frac * cam.width_px + 0.1 * (last.peak_px - last.base_px).norm();
      for (int s = 0; s < static_cast<int>(frame.cones.size()); ++s) {
        const ConeSighting& c = frame.cones[s];
        const double cost = 0.5 * ((c.peak_px - peak).norm() + (c.base_px - base).norm());
        const double len_ratio = (c.peak_px - c.base_px).norm() / std::max(1.0, (peak - base).norm());
        if (cost < gate && len_ratio > 0.85 && len_ratio < 1.0 / 0.85) pairs.push_back({cost, t, s});
      }
    }
    std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.cost < b.cost; });
    std::vector<bool> track_used(open.size(), false), sighting_used(frame.cones.size(), false);
    for (const Pair& p : pairs) {
      if (track_used[p.track] || sighting_used[p.sighting]) continue;
      track_used[p.track] = sighting_used[p.sighting] = true;
      open[p.track].sightings.emplace_back(f, p.sighting);
    }
    for (int s = 0; s < static_cast<int>(frame.cones.size()); ++s)
      if (!sighting_used[s]) open.push_back(Track{{{f, s}}});
  }
  done.insert(done.end(), open.begin(), open.end());
  std::vector<Track> kept;
  for (const Track& t : done)
    if (static_cast<int>(t.sightings.size()) >= config.min_track_frames) kept.push_back(t);
  return kept;
}

}  // namespace cone_survey
