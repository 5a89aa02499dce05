// Pinhole camera with the thesis's radial + tangential distortion (3.10), the
// same polynomial as ROS's plumb_bob model (D = [k1 k2 p1 p2 k3]).
// ROS-free. Pixel centres are at integer coordinates (the camera_info convention).
#pragma once

#include <string>

#include <Eigen/Core>

namespace rig_sim {

struct CameraConfig {
  int width_px = 1024;
  int height_px = 768;
  double fu_px = 770.0;  // effective focal lengths of the thesis's rig (ch. 7)
  double fv_px = 776.0;
  double cu_px = 511.5;  // principal point at the image centre
  double cv_px = 383.5;
  // A 3.5 mm wide-angle C-mount lens (the thesis's Kowa LM4NCL) has mild
  // barrel distortion; the thesis gives no numbers, these are typical.
  double k1 = -0.22;
  double k2 = 0.07;
  double p1 = 0.0008;
  double p2 = -0.0005;
  double k3 = 0.0;
  double rate_hz = 30.0;

  // The same lens on a sensor scaled by `factor` (e.g. 0.25 for 256x192).
  CameraConfig Scaled(double factor) const;
  // Empty when valid, else a message naming the bad field.
  std::string Validate() const;
};

class CameraModel {
 public:
  explicit CameraModel(const CameraConfig& config);
  const CameraConfig& config() const { return config_; }

  // Undistorted normalised point (x/z, y/z) -> distorted normalised point (3.10).
  Eigen::Vector2d Distort(const Eigen::Vector2d& undistorted) const;
  // Inverse of Distort (3.11) by Newton's method; converged to ~1e-12.
  Eigen::Vector2d Undistort(const Eigen::Vector2d& distorted) const;
  // Point in camera_optical -> pixel (u, v). Returns false behind the camera.
  bool Project(const Eigen::Vector3d& p_in_camera, Eigen::Vector2d* uv_px) const;
  // Pixel -> unit-free ray direction (x, y, 1) in camera_optical.
  Eigen::Vector3d PixelRay(double u_px, double v_px) const;

 private:
  CameraConfig config_;
};

}  // namespace rig_sim
