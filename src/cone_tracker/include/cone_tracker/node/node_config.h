// Parameters of the cone_tracker nodelet: one struct, filled and validated by
// LoadConfig (names are the private parameters' names, units in the names).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "cone_tracker/vision/cone_detector.h"
#include "cone_tracker/vision/cone_pose.h"
#include "cone_tracker/vision/segmenter.h"

namespace ros {
class NodeHandle;
}

namespace cone_tracker {

struct DebugImageConfig {
  bool tint_mask = true;      // colour the classified cone pixels
  bool draw_rejected = true;  // outline rejected blobs with their failed gates
  bool draw_text = true;      // ids, gate outcome, chi-square
};

struct NodeConfig {
  std::string layout_file;                      // rig_model layout schema (layout.h); required
  std::string fixed_frame = "cones";            // header.frame_id of the pose and the markers
  std::string camera_frame = "camera_optical";  // child frame of the tf prediction (pose_ekf's)
  // Prediction for correspondence and the motion gate (3.1.6, 6.4.2): tf
  // fixed_frame -> camera_frame at the image stamp (pose_ekf), else the latest
  // transform if not older than prediction_max_age_s, else the last accepted
  // pose if not older than that, else none (linear initialisation).
  bool use_tf_prediction = true;
  double prediction_max_age_s = 0.5;
  // Track lost: no pose accepted for this long (after an outage pose_ekf coasts
  // on the gyros and its position drifts, so its prediction may match no cone).
  // A frame whose prediction then fails is solved again without it: the linear
  // algorithms re-initialise (3.1.6), the prediction's bearing breaking the tie.
  double reacquire_after_s = 1.0;
  // The two-cone start (vision/two_cone_pose.h): without a prediction, a frame with exactly two cones is
  // solved with the accelerometer's "up" (imu/data_raw, the mean over gravity_window_s around the image
  // stamp, turned into camera_frame by tf) as a prior on the tilt with this 1-sigma error. 0: off (three
  // cones start the track, as in the thesis).
  double two_cone_gravity_sigma_deg = 3.0;
  double gravity_window_s = 0.1;
  // Tie-break among the rotations of a symmetric layout without a prediction:
  // the camera's bearing around the layout, atan2(y, x) of its position in
  // `cones` (deg). NaN: none.
  double heading_prior_deg = NAN;
  // Per-cone association through the prediction (cone_tracker/observations,
  // pose/associate.h): the prediction's 1-sigma error per axis, added to
  // pose_ekf's covariance (pose_ekf/pose) with the tf prediction; without that
  // covariance its position part grows by prediction_drift_m_s since the last
  // frame with a pose or two associated cones, up to prediction_max_sigma_m. A
  // detection keeps its cone only if every other cone costs association_margin
  // more (chi-square).
  double prediction_sigma_m = 0.05;
  double prediction_sigma_deg = 2.0;
  double prediction_drift_m_s = 0.5;
  double prediction_max_sigma_m = 1.0;
  double association_margin = 9.0;
  // An assignment that puts a layout cone it leaves unmatched in plain view, or partly in view where the image has no
  // orange, costs this much more (AssociationConfig::miss_cost, negative information); 0: off (the rig, until its
  // detector's P_D is measured).
  double association_miss_cost = 0.0;
  // Per orange box that an assignment's pose puts no layout cone near, nor a detection (AssociationConfig's
  // unexplained_cost); 0: off.
  double association_unexplained_cost = 0.0;
  double expected_rate_hz = 30.0;  // diagnostics' frequency check on published poses
  double rate_tolerance = 0.5;     // +-50 % of expected_rate_hz
  SegmenterConfig segmenter;
  ConeDetectorConfig detector;  // colour segmentation (default) or the learned detector for photos
  ConePoseConfig pose;
  DebugImageConfig debug;
};

// Throws std::invalid_argument naming the bad parameter (or layout field).
// The layout file itself is read by the adapter (LoadLayoutFile).
NodeConfig LoadConfig(const ros::NodeHandle& private_nh);
// Validates everything but the layout file; throws std::invalid_argument.
void ValidateConfig(const NodeConfig& config);

}  // namespace cone_tracker
