#include "rig_sim/sim_stream.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

namespace rig_sim {

SimStream::SimStream(const Scenario& scenario, const StreamConfig& config)
    : scenario_(scenario),
      config_(config),
      trajectory_(scenario.trajectory),
      imu_(scenario.imu, trajectory_),
      renderer_(scenario.camera.model, scenario.scene, scenario.render) {
  const std::string cam_err = scenario.camera.Validate();
  if (!cam_err.empty()) throw std::invalid_argument("CameraConfig: " + cam_err);
  if (!(config.truth_rate_hz > 0.0) || !(config.camera_delay_s >= 0.0) || config.camera_delay_s > 1.0)
    throw std::invalid_argument("StreamConfig: truth_rate_hz must be positive, camera_delay_s in [0, 1] s");
  pending_imu_ = imu_.Next();
}

bool SimStream::Next(SimEvent* e) {
  const double end = scenario_.trajectory.duration_s;
  // Stamps are integer multiples of each period from t = 0 (IMU from its first full interval).
  const double t_imu = pending_imu_.stamp_s;
  const double t_truth = next_truth_ / config_.truth_rate_hz;
  const double t_image = next_image_ / scenario_.camera.rate_hz;
  const double d_image = t_image + config_.camera_delay_s;
  const bool imu_ok = t_imu < end, truth_ok = t_truth < end, image_ok = t_image < end;
  if (!imu_ok && !truth_ok && !image_ok) return false;
  // Delivery order; ties go IMU, truth, image (the camera result is the slowest).
  const double inf = 1e300;
  const double a = imu_ok ? t_imu : inf, b = truth_ok ? t_truth : inf, c = image_ok ? d_image : inf;
  *e = SimEvent();
  if (a <= b && a <= c) {
    e->kind = EventKind::kImu;
    e->stamp_s = e->deliver_s = t_imu;
    e->index = next_imu_++;
    e->imu = pending_imu_;
    pending_imu_ = imu_.Next();
  } else if (b <= c) {
    e->kind = EventKind::kTruth;
    e->stamp_s = e->deliver_s = t_truth;
    e->index = next_truth_++;
  } else {
    e->kind = EventKind::kImage;
    e->stamp_s = t_image;
    e->deliver_s = d_image;
    e->index = next_image_++;
  }
  e->pose = trajectory_.At(e->stamp_s);
  if (e->kind == EventKind::kTruth) e->omega_camera_rad_s = trajectory_.OmegaCamera(e->stamp_s);
  return true;
}

SimEvent SimStream::ImageEventAt(double t_s, uint64_t index) const {
  SimEvent ev;
  ev.kind = EventKind::kImage;
  ev.stamp_s = ev.deliver_s = t_s;
  ev.index = index;
  ev.pose = trajectory_.At(t_s);
  return ev;
}

void SimStream::RenderFrame(const SimEvent& ev, uint8_t* rgb, int16_t* labels) const {
  const AppearanceConfig& a = scenario_.render.appearance;
  if (a.exposure_time_s > 0.0 && a.blur_samples > 1) {  // motion blur: the poses while the shutter is open
    // How far the image moves during the exposure (px): the rotation, and the translation as seen at
    // 1 m. One pose per ~2 px of motion (odd, so the middle pose is the stamp's), at most blur_samples:
    // a still rig costs one render.
    const TruePose first = trajectory_.At(ev.stamp_s - 0.5 * a.exposure_time_s);
    const TruePose last = trajectory_.At(ev.stamp_s + 0.5 * a.exposure_time_s);
    const double angle_rad = Eigen::AngleAxisd(first.R_cones_camera.transpose() * last.R_cones_camera).angle();
    const double shift_m = (last.p_camera_in_cones_m - first.p_camera_in_cones_m).norm();
    const double motion_px = scenario_.camera.model.fx_px * (angle_rad + shift_m / 1.0);
    const int n = motion_px < 0.25 ? 1 : std::min(a.blur_samples, 2 * static_cast<int>(std::ceil(motion_px / 4.0)) + 1);
    if (n > 1) {
      std::vector<TruePose> poses;
      for (int k = 0; k < n; ++k)
        poses.push_back(trajectory_.At(ev.stamp_s + a.exposure_time_s * ((k + 0.5) / n - 0.5)));
      renderer_.RenderExposure(poses, ev.stamp_s, ev.index, rgb, labels);
      return;
    }
  }
  renderer_.Render(ev.pose, ev.stamp_s, ev.index, rgb, labels);
}

}  // namespace rig_sim
