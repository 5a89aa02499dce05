// A near cone's tip seen in front of a farther cone of the same colour. The tip and the far cone's body are one
// 8-connected patch of orange, so the tip joins the far cone's blob: the near cone's blob ends at its first band,
// short of its apex, and fails the outline's tip check, and the far one, with a tip sticking out of it, fails too
// (rig_sim's look_away seed 52 after its outage: two cones one behind the other, nothing measured for ten frames).
// The near cone's two edges still fit, and say where its tip is: between them, from the blob's top to the apex.
// ROS-free.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "cone_tracker/pose/pnp.h"
#include "cone_tracker/vision/blobs.h"
#include "cone_tracker/vision/cone_outline.h"

namespace cone_tracker {

struct TipPiece {
  std::vector<Run> tip;   // the other blob's pixels inside the cone's edges, toward its apex (raw px)
  std::vector<Run> rest;  // the other blob's pixels outside the cone (its mixed edge pixels are in neither)
  int rows = 0;           // rows of `tip`
  // Rows where the tip ends on one of the edge lines against the background (the other blob's run ends there, inside
  // the image, and its outer pixel boundary is within edge_px of the line); the larger count of the two sides. A tip in
  // front of a cone's body shows at least one of its edges over its length; orange that only fills the wedge does not.
  int edge_rows = 0;
  Eigen::Vector2d base_end_px = Eigen::Vector2d::Zero();  // the tip's pixel nearest the near cone's base (raw)
};

// The part of a cone's silhouette above its blob's top: between the two edge lines of an outline fit (undistorted
// px, positive inside), along the axis from the apex to top_t_px; with its raw bounding box (2 px of margin: the lens
// bends its sides a little). Made once per blob, then searched in every other blob.
struct TipWedge {
  Eigen::Vector2d apex_undist_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d axis_dir = Eigen::Vector2d::Zero();  // unit, undistorted, from the apex toward the base
  Eigen::Vector3d left_line = Eigen::Vector3d::Zero(), right_line = Eigen::Vector3d::Zero();
  double top_t_px = 0.0;
  int x0 = 0, x1 = -1, y0 = 0, y1 = -1;
};
// fit's lines and apex must be set (OutlineFit::apex_undist_px). False when top_t_px <= 0 or the lens model fails.
bool MakeTipWedge(const OutlineFit& fit, const Eigen::Vector2d& axis_dir, double top_t_px, const CameraModel& camera,
                  TipWedge* wedge);

// The pixels of `other` (raw px) whose centres lie in the wedge. Those within half a pixel outside an edge or the apex
// go to neither `tip` nor `rest`. width_px: the image's (a run ending on its edge ends on no background).
TipPiece FindTipIn(const std::vector<Run>& other, const TipWedge& wedge, const CameraModel& camera, double edge_px,
                   int width_px);

}  // namespace cone_tracker
