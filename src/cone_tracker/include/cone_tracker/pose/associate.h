// Association of detected cones with the layout through a predicted pose, for
// any number of cones (1, 2, 3 or more), and the 2x2 covariance of each image
// point: the per-cone measurements of cone_tracker/observations. ROS-free.
//
// Every layout cone's peak, mid and base (3.12, corrected for the predicted
// eye, 3.1.4) is projected with the prediction; its spread is the prediction's
// error (camera orientation and position, 1-sigma per axis) pushed through the
// projection, plus the image noise. The cones' predicted points move together
// with the pose, so an assignment is scored on all its matched cones at once:
// the camera pose that best explains them under the prediction (Gauss-Newton
// on the prior term plus the pixel term, relinearised at every step) and its
// cost, so a common shift costs little, a swap of two cones of different
// height or spacing costs a lot, and a prediction metres off (pose_ekf's after
// an outage, with its covariance) is judged at the pose the pair puts the
// camera, not by the projection's first-order change at the prediction.
// Only the peak and the base are scored: every detector here sets the mid to
// the image midpoint of its peak and base, which is not where the 3-D
// midpoint projects (1.4-2.1 px off at 512x384, more on a near cone), and
// carries nothing the two do not (pose_ekf fuses the same two points).
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cone_tracker/pose/pnp.h"
#include "pose_math/pose.h"
#include "rig_model/cone_view.h"

namespace cone_tracker {

using ConePoints2d = std::array<Eigen::Vector2d, 3>;  // peak, mid, base in undistorted px
using ConePoints3d = std::array<Eigen::Vector3d, 3>;  // peak, mid, base in `cones` (m)

struct AssociationConfig {
  double sigma_px = 1.0;                // image noise per coordinate (ConePoseConfig::sigma_px)
  double prediction_sigma_m = 0.05;     // camera position error of the prediction, per axis
  double prediction_sigma_rad = 0.035;  // camera orientation error of the prediction, per axis
  // The prediction's full covariance over (camera rotation, in the camera frame; camera position in
  // `cones`), e.g. pose_ekf's; when set it replaces the two sigmas above.
  std::optional<Eigen::Matrix<double, 6, 6>> prediction_cov;
  int fit_iterations = 8;           // Gauss-Newton steps of an assignment's fit (0: first order at the prediction)
  double gate_probability = 0.999;  // a pair fits when chi2(4 dof) of its peak and base is below this quantile
  double ambiguity_margin = 9.0;    // a detection keeps its cone only if every other cone for it costs this much more
  double outside_frac =
      0.5;  // a cone predicted farther outside the image than this fraction of its size is no candidate
  double min_depth_m = 0.1;  // a cone point nearer than this (or behind the camera) is no candidate
  // Cones predicted to overlap by more than this many sigmas of their predicted offset are no candidates (fewer: they
  // are, but no evidence of a conflict).
  double overlap_sigmas = 2.0;
  size_t max_assignments = 200000;  // enumeration bound; beyond it nothing is associated
  // Negative information: an assignment whose fitted pose puts a layout cone it leaves unmatched in plain
  // view, or partly in view where the image has no orange (rig_model/cone_view.h), costs this much more per such
  // cone, -2 ln(1 - P_D); 0: off. Below the ambiguity margin, a miss alone never makes a wrong cone win: it can
  // only make a detection ambiguous.
  double miss_cost = 0.0;
  // And per orange box (SegmentationResult::orange_undist_px: up to kOrangeSlabs a blob) that its pose puts no layout
  // cone near, nor any detection (rig_model::UnexplainedOrange): orange left to clutter; 0: off.
  double unexplained_cost = 0.0;
  rig_model::PlainViewRule plain_view;
  std::string Validate() const;
};

struct ConeCandidate {
  int cone = -1;                             // layout index
  Eigen::Matrix<double, 6, 1> predicted_px;  // peak u v, mid u v, base u v
  Eigen::Matrix<double, 6, 6> jacobian;      // d predicted_px / d (camera rotation, camera position)
};

struct AssociationResult {
  std::vector<int> cone_of_detection;  // layout index per detection, -1: none
  std::vector<double> d2;  // per detection: chi2 of its peak and base against its cone's prediction (NaN: none)
  std::vector<ConeCandidate> candidates;  // layout cones in front of the camera, near the image, apart
  std::vector<int> overlapping;  // layout cones left out: predicted to overlap another in the image (overlap_sigmas)
  int ambiguous = 0;             // detections left out: another cone fitted them nearly as well
  bool too_many = false;         // the enumeration bound was reached: nothing associated
  // A detection left unmatched lies on an unmatched candidate's predicted base (chi2 of
  // the base point below the 2-dof gate) but does not fit its shape: the
  // prediction is off by a swap of cones, or the segmentation by a cut cone;
  // either way nothing in the frame is associated.
  bool conflict = false;
  double cost = 0.0;  // of the chosen assignment (chi2 units, unmatched detections at the gate, misses, clutter)
  int misses = 0;     // of the chosen assignment: layout cones it puts in plain view that no detection is
  int fits = 0;       // assignments (and partial ones) fitted
};

// The prior of AssociationConfig::prediction_cov from a camera pose's covariance as ROS publishes
// it (pose_ekf/pose: x y z, then small rotations about the fixed axes of `cones`, R' = Exp(dtheta) R
// for R = R(q_cones_camera)): the rotation taken into the camera frame, the position kept.
Eigen::Matrix<double, 6, 6> AssociationPrior(const pose_math::Quat& q_cones_camera,
                                             const Eigen::Matrix<double, 6, 6>& cov_ros);

// A layout cone's points seen from an eye (the camera's position in `cones`): (3.18) moves the peak and
// base with the viewpoint (cone_pose.h's CorrectedModelPoints), so an assignment's fit, which moves the
// camera metres after an outage, asks for them at every pose it tries.
using ModelPointsAt = std::function<ConePoints3d(size_t cone, const Eigen::Vector3d& p_camera_in_cones_m)>;

// Every layout cone's silhouette seen from a camera at `eye` (in `cones`) turned by R_camera_cones, unclipped;
// nullopt for a cone whose peak or base is not min_depth_m in front of the camera. What rig_model::MissedInView
// judges (the association's misses, the two-cone start's).
std::vector<std::optional<rig_model::ConeSilhouette>> LayoutSilhouettes(const ModelPointsAt& model, size_t num_cones,
                                                                        const Eigen::Matrix3d& R_camera_cones,
                                                                        const Eigen::Vector3d& eye,
                                                                        const CameraModel& cam, double min_depth_m);

// detections: undistorted points; point_cov: their 2x2 covariances (PointCovariances);
// model: the points of layout cones 0 .. num_cones - 1 (cone_pose.h's LayoutSeenFrom); camera: the pinhole of
// the undistorted pixels; orange: where the image is orange, in undistorted pixels (SegmentationResult's
// orange_undist_px; empty: not known, only cones in plain view are missed).
AssociationResult AssociateCones(const std::vector<ConePoints2d>& detections,
                                 const std::vector<std::array<Eigen::Matrix2d, 3>>& point_cov, size_t num_cones,
                                 const ModelPointsAt& model, const CameraModel& camera,
                                 const pose_math::Pose& T_camera_cones_pred, const AssociationConfig& config,
                                 const std::vector<rig_model::ImageBox>& orange = {});

// The 2x2 covariances (px^2) of a detected cone's peak, mid and base: sigma_px
// per coordinate (the point noise of the 5.6 covariance) for all three, and for
// the peak an extra spread along the cone's axis: the segmentation ends the
// axis line search (3.1.5.4) at the last cone pixel, but the silhouette is
// narrower than a pixel over the last h/w px of the tip (h the peak-base
// length, w the base width, w = 2 area / h for a triangle), so the found peak
// lies anywhere on that stretch: variance (h/w)^2 / 12 along the axis.
std::array<Eigen::Matrix2d, 3> PointCovariances(const ConePoints2d& points_px, double area_px, double sigma_px);

}  // namespace cone_tracker
