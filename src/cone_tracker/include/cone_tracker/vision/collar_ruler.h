// A cone whose base is cut by the image's edge, measured by its collars. The border gate refuses a cut cone: its
// base, and with it the cone's size in the image, is outside. But a road cone's white collars stand at known
// fractions of its height, and on the image of the line from its apex down its front (the outline's axis line,
// cone_outline.h) the heights map to the pixels by a 1-D projective map: the apex and the collars' edges fix it, and
// it gives where the mid-height point and the base (3.1.4's front points) project, in the image or past its edge.
// What that buys: the first cone back after an outage is often cut (rig_sim look_away seed 35, pose_ekf README),
// and a cut cone's apex alone fixes the camera only across its ray. ROS-free.
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cone_tracker/pose/pnp.h"
#include "cone_tracker/vision/cut_cone.h"

namespace cone_tracker {

struct CollarRulerConfig {
  // The collars as (from, to) fractions of the height above the base (rig_model's ConeSpec::collars); empty: off.
  std::vector<std::pair<double, double>> collars;
  // A pixel is a collar's when its smallest channel is at least this share of its largest (white or silver: near 1;
  // safety orange: under 0.25).
  double white_ratio = 0.5;
  // The largest residual of the collar edges about the fitted map (undistorted px) that still reads as one cone's.
  double max_residual_px = 0.6;
  // A collar edge's localisation error (px, 1 sigma): the map's, and so the mid and base points', uncertainty.
  double edge_sigma_px = 0.3;
  std::string Validate() const;  // "" or what is wrong, naming the field (as SegmenterConfig::collar.*)
};

struct CollarReading {
  bool ok = false;
  std::string why;               // when !ok
  std::vector<double> edges_px;  // the collar edges found, distance along the axis from the apex given
  double residual_px = 0.0;      // the largest, about the map
  // Peak, mid and base (3.1.4's front points), undistorted px, and their errors along the axis (1 sigma, px) from
  // the edges' sigma through the map.
  std::array<Eigen::Vector2d, 3> points_undist_px{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(),
                                                  Eigen::Vector2d::Zero()};
  Eigen::Vector3d axis_sigma_px = Eigen::Vector3d::Zero();
};

// Reads the collars down the axis from apex_undist_px (undistorted px) in direction axis_dir (unit, toward the base),
// sampling the raw frame through the lens model from start_px on (past the tip, where the silhouette is a few pixels
// wide). apex_known: the peak is the apex given (the map has two parameters); else the collars place it along the
// axis too (three). ok when the cone runs out of the image before its base (every collar edge above the image's edge
// read, no more: ground after the last collar means the base is in view, and the border gate's refusal stands), at
// least one edge more than the map's parameters is read, and they fit the map within max_residual_px.
CollarReading ReadCollars(const RgbView& image, const CameraModel& camera, const Eigen::Vector2d& apex_undist_px,
                          const Eigen::Vector2d& axis_dir, double start_px, bool apex_known,
                          const CollarRulerConfig& config);

}  // namespace cone_tracker
