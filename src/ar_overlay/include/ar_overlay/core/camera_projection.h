// The camera side of the renderer: intrinsics in OpenCV's convention, the
// OpenGL projection built from them, and the map that puts a pinhole
// (undistorted) rendering onto the raw, distorted image.
//
// Lens distortion: we render an ideal pinhole image on a canvas a little larger
// than the camera image (barrel distortion pulls the raw image's corners in from
// outside the pinhole frame), then cv::remap it with a map built from the
// camera's plumb_bob coefficients, so the overlay lines up with the raw image
// the user sees. Compositing on the rectified image instead would need the
// camera image remapped every frame, which costs the same and loses the
// camera's own pixels at the border.
#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <vector>

#include "rig_model/camera_model.h"

namespace ar_overlay {

// The rig's camera (rig_model): intrinsics in OpenCV's convention and the plumb_bob or
// rational_polynomial coefficients in OpenCV's order; rig_model::Validate checks it.
using CameraModel = rig_model::CameraModel;

// OpenGL clip-from-camera matrix for camera coordinates in OpenCV's optical
// convention (x right, y down, z forward), so that pixel (u, v) = (fx x/z + cx,
// fy y/z + cy) with pixel centres at integers lands on the centre of pixel
// (u, v) in a width x height framebuffer whose row 0 is the image's top row
// (glReadPixels then returns the rows in image order). Depth maps [near, far]
// to [-1, 1].
Eigen::Matrix4f ProjectionFromIntrinsics(double fx, double fy, double cx, double cy, int width, int height,
                                         double near_m, double far_m);

// T_cones_camera for an optical frame at `eye` looking at `target` with the
// image's up toward +z (for demos, tests and the benchmark).
Eigen::Isometry3d CameraLookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);

// Where the pinhole rendering goes, and how it reaches the raw image.
class DistortionMap {
 public:
  // Builds the canvas and the map for `k` (slow: call when the intrinsics change).
  explicit DistortionMap(const CameraModel& k);

  int canvas_width() const { return canvas_width_; }
  int canvas_height() const { return canvas_height_; }
  // Principal point on the canvas (the camera's, shifted by the canvas margin).
  double canvas_cx() const { return canvas_cx_; }
  double canvas_cy() const { return canvas_cy_; }
  // True when the canvas is the camera image itself (no distortion): no remap.
  bool identity() const { return identity_; }
  // The raw-image-sized view of a canvas-sized rendering.
  void Apply(const cv::Mat& canvas, cv::Mat& raw) const;
  // The raw pixels whose map lands in `canvas_roi` (a bounding box, clipped to
  // the image), and the remap of those pixels only: raw(raw_roi) from canvas.
  cv::Rect RawRoi(const cv::Rect& canvas_roi) const;
  void ApplyRoi(const cv::Mat& canvas, const cv::Rect& raw_roi, cv::Mat& raw) const;

 private:
  int canvas_width_ = 0, canvas_height_ = 0;
  double canvas_cx_ = 0, canvas_cy_ = 0;
  bool identity_ = true;
  cv::Mat map1_, map2_;  // fixed-point maps for cv::remap
  cv::Matx33d K_;
  std::vector<double> distortion_;
};

}  // namespace ar_overlay
