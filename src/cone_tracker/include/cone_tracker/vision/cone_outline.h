// Sub-pixel peak and base from the cone's outline (refines 3.1.5.3's line
// search; the alternative to 3.1.5.4's templates, see segmenter.h).
//
// The silhouette of an upright cone is two straight edges (the images of its
// contour generators) meeting at the apex, closed by the front arc of the
// base ellipse. Fitting the two edges over every row of the blob and
// intersecting them finds the apex even where the tip is narrower than a pixel
// and vanishes from the binary mask. The cone and the camera centre are
// mirror-symmetric about the plane through the cone's axis, so that plane's
// image (the axis line) is the projective bisector of the two edges; the
// base point facing the camera (3.1.4's model point) lies in that plane, i.e.
// where the axis line meets the front arc. All of it is done on undistorted
// pixels, where these lines are straight. ROS-free.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "cone_tracker/pose/pnp.h"
#include "cone_tracker/vision/blobs.h"

namespace cone_tracker {

struct OutlineConfig {
  double outlier_px = 1.0;        // edge points farther than this from their line are not on it
  double max_edge_rms_px = 0.8;   // RMS distance of the inlying edge points to their lines, and of the base arc's
  double min_inlier_frac = 0.25;  // of the rows above the base arc, per edge
  double max_outward_frac =
      0.15;  // edge points outside their line by > outlier_px, per edge (demosaicing fringes reach 6%)
  double max_apex_gap_frac = 0.05;  // apex off the line search's axis, fraction of the height (+ 3 px)
  double max_tilt_deg = 60.0;       // edges are sampled per row: the axis must be roughly vertical
};

struct OutlineFit {
  bool ok = false;
  std::string why;                                                                       // when !ok: which check failed
  Eigen::Vector2d peak_px = Eigen::Vector2d::Zero(), base_px = Eigen::Vector2d::Zero();  // raw pixels
  Eigen::Vector2d peak_undist_px = Eigen::Vector2d::Zero(), base_undist_px = Eigen::Vector2d::Zero();
  // Undistorted px, positive inside the silhouette; set with apex_undist_px (below).
  Eigen::Vector3d left_line = Eigen::Vector3d::Zero(), right_line = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_line = Eigen::Vector3d::Zero();
  double edge_rms_px = 0.0;
  double inlier_frac = 0.0;   // the smaller of the two edges'
  double outward_frac = 0.0;  // the larger of the two edges'
  double arc_rms_px = 0.0;    // the base arc's points about their parabola
  // How far short of the apex the silhouette may end (sensor px along the axis): where it is narrower than about a
  // pixel, 3 px + 1/tan of the edges' half-angle. The tip check lets the blob's tip stop that short of the fitted apex,
  // and the segmenter lets a cone touch the image's edge only there (segmenter.h, border_px).
  double tip_zone_px = 0.0;
  // Set once the two edges fit and meet, also when a later check fails: the apex (undistorted px), and how far short
  // of it the blob's tip stops (sensor px along the axis; negative past it). The tip check wants it within
  // [-1.5, tip_zone_px]; a blob that stops short by more may have its tip in another blob (merged_tip.h).
  Eigen::Vector2d apex_undist_px = Eigen::Vector2d::Zero();
  double tip_short_px = 0.0;
};

// runs: the blob's pixels; peak_guess_px / base_guess_px: the line search's
// ends (raw pixels). camera with fx_px <= 0: no undistortion, and the axis is
// the Euclidean bisector (no intrinsics to make it projective).
OutlineFit FitConeOutline(const std::vector<Run>& runs, const Eigen::Vector2d& peak_guess_px,
                          const Eigen::Vector2d& base_guess_px, const CameraModel& camera, const OutlineConfig& config);

// The axis line (the image of the plane through the cone's axis and the camera centre): the projective bisector of
// the two edges (OutlineFit's left_line and right_line, undistorted px). camera with fx_px <= 0: the Euclidean one.
Eigen::Vector3d OutlineAxisLine(const Eigen::Vector3d& left_line, const Eigen::Vector3d& right_line,
                                const CameraModel& camera);

// Forward lens model: undistorted (ideal, same K) pixels -> raw pixels. The
// inverse of UndistortPixels (segmenter.h). False on non-finite output.
bool DistortPixels(const CameraModel& camera, std::vector<Eigen::Vector2d>* points_px);

}  // namespace cone_tracker
