// The rig's camera: a pinhole with ROS's plumb_bob or rational_polynomial distortion, the thesis's
// radial + tangential model (3.10) in OpenCV's coefficient order, so the same struct goes to
// cv::undistortPoints/projectPoints unchanged. One struct for the tracker, the simulator and the
// overlay; rig_model_ros converts it to and from sensor_msgs/CameraInfo. ROS-free.
// Pixel centres are at integer coordinates (the camera_info convention).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace rig_model {

enum class DistortionModel {
  kPlumbBob,            // k1 k2 p1 p2 [k3]
  kRationalPolynomial,  // k1 k2 p1 p2 k3 k4 k5 k6: radial (1 + k1 r² + k2 r⁴ + k3 r⁶) / (1 + k4 r² + k5 r⁴ + k6 r⁶)
};

// "plumb_bob" / "rational_polynomial", as in sensor_msgs/CameraInfo.
std::string DistortionModelName(DistortionModel model);
// False for any other name.
bool DistortionModelFromName(const std::string& name, DistortionModel* model);

struct CameraModel {
  int width_px = 0;
  int height_px = 0;
  double fx_px = 0.0;  // focal lengths (fu, fv of 3.10)
  double fy_px = 0.0;
  double cx_px = 0.0;  // principal point (u0, v0)
  double cy_px = 0.0;
  std::vector<double> distortion;  // OpenCV order k1 k2 p1 p2 [k3 [k4 k5 k6]]; empty or all zero: none
  DistortionModel distortion_model = DistortionModel::kPlumbBob;

  bool HasDistortion() const;
  bool operator==(const CameraModel& o) const;
  bool operator!=(const CameraModel& o) const { return !(*this == o); }

  // Undistorted normalised point (x/z, y/z) -> distorted normalised point (3.10).
  Eigen::Vector2d Distort(const Eigen::Vector2d& undistorted) const;
  // d Distort / d undistorted at `undistorted`.
  Eigen::Matrix2d DistortJacobian(const Eigen::Vector2d& undistorted) const;
  // Inverse of Distort (3.11) by Newton's method (at most 50 steps, until a step is below 1e-14).
  Eigen::Vector2d Undistort(const Eigen::Vector2d& distorted) const;
  // Point in the optical frame -> pixel (u, v), and optionally d(u, v) / d(point). False behind
  // the camera (z <= 1e-9); the outputs are untouched then.
  bool Project(const Eigen::Vector3d& p_in_camera, Eigen::Vector2d* uv_px,
               Eigen::Matrix<double, 2, 3>* J_uv_point = nullptr) const;
  // Pixel -> ray direction (x, y, 1) in the optical frame, undistorted.
  Eigen::Vector3d PixelRay(double u_px, double v_px) const;
  // The same lens on a sensor scaled by `factor` (e.g. 0.25 for 256x192), principal point kept at
  // the same place in the scaled image.
  CameraModel Scaled(double factor) const;
};

// Empty when usable, else a message naming the bad field.
std::string Validate(const CameraModel& camera);

// The thesis's rig (ch. 7): 1024x768, fu = 770, fv = 776, principal point at the image centre, and
// the mild barrel distortion of a 3.5 mm wide-angle C-mount lens (the thesis's Kowa LM4NCL; it gives
// no numbers, these are typical): plumb_bob (-0.22, 0.07, 0.0008, -0.0005, 0).
CameraModel ThesisCamera();

}  // namespace rig_model
