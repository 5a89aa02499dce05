#include "cone_tracker/testing/vision_frames.h"

#include <Eigen/Geometry>

#include "rig_sim/renderer.h"

namespace cone_tracker {

rig_sim::TruePose LookAt(const Eigen::Vector3d& eye_m, const Eigen::Vector3d& target_m) {
  const Eigen::Vector3d z = (target_m - eye_m).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();  // right
  const Eigen::Vector3d y = z.cross(x);                                      // down
  rig_sim::TruePose p;
  p.R_cones_camera.col(0) = x, p.R_cones_camera.col(1) = y, p.R_cones_camera.col(2) = z;
  p.p_camera_in_cones_m = eye_m;
  return p;
}

ImageView FrameView(const SimFrame& f, const std::string& encoding) {
  return {f.rgb.data(), f.camera.width_px, f.camera.height_px, f.camera.width_px * 3, encoding};
}

SimFrame RenderSim(const rig_sim::Scene& scene, const rig_sim::TruePose& pose, const CameraModel& camera,
                   double noise_sigma_dn) {
  rig_sim::RenderConfig rc;
  rc.noise_sigma_dn = noise_sigma_dn;
  rc.lighting.variation = 0.0;
  const CameraModel& cam = camera;
  const rig_sim::Renderer renderer(cam, scene, rc);
  SimFrame f;
  f.camera = camera;
  f.pose = pose;
  f.rgb.resize(size_t(renderer.width()) * renderer.height() * 3);
  renderer.Render(pose, 1.0, 0, f.rgb.data());
  const Eigen::Matrix3d R_camera_cones = pose.R_cones_camera.transpose();
  auto project = [&](const Eigen::Vector3d& p_cones) {
    Eigen::Vector2d uv(NAN, NAN);
    cam.Project(R_camera_cones * (p_cones - pose.p_camera_in_cones_m), &uv);
    return uv;
  };
  for (const rig_sim::ConeSpec& c : scene.cones) {
    Eigen::Vector3d toward = pose.p_camera_in_cones_m - c.base_m;
    toward.z() = 0.0;
    toward.normalize();
    f.truth.push_back({project(c.peak_m()), project(c.base_m + c.radius_m() * toward)});
  }
  return f;
}

}  // namespace cone_tracker
