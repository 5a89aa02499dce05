// The cone survey (ROS-free core of survey_layout): from a walk around the placed cones (each
// frame's detected cone points and the IMU), where every cone stands. Cones are tracked from frame
// to frame with the gyro's rotation as the prediction, the tracks are placed by a linear
// structure-from-motion with the IMU's rotations (z up from the accelerometer), grouped into cones
// and matched to the inventory by height (the known heights give the scale), then every cone
// position, camera pose and the gyro bias are refined by bundle adjustment (Ceres) over the cones'
// peak and base points, corrected for the eye as the tracker does (3.16) (3.17) (3.18), with a
// robust loss, the gyro's relative rotations and the accelerometer's gravity direction. The frame
// is the inventory's: origin at its origin cone, +x toward its +x cone, z up.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "cone_survey/inventory.h"
#include "rig_model/camera_model.h"

namespace cone_survey {

// One detected cone in a frame: the segmentation's undistorted peak and base pixels (pinhole K of
// the camera, 3.1.2).
struct ConeSighting {
  Eigen::Vector2d peak_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d base_px = Eigen::Vector2d::Zero();
};
struct SurveyFrame {
  double stamp_s = 0.0;  // exposure
  std::vector<ConeSighting> cones;
};
// An IMU sample in the IMU frame, stamped at the middle of the interval it covers (REP-145).
struct ImuReading {
  double stamp_s = 0.0;
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();
};
struct SurveyInput {
  rig_model::CameraModel camera;
  Eigen::Matrix3d R_camera_imu = Eigen::Matrix3d::Identity();  // v_camera = R v_imu
  std::vector<SurveyFrame> frames;                             // in stamp order
  std::vector<ImuReading> imu;                                 // in stamp order
};

struct SurveyConfig {
  double track_gate_frac = 0.025;     // frame-to-frame match gate: this x image width (+ 0.1 x the cone's length)
  int track_max_gap_frames = 3;       // a track missing this many frames ends
  int min_track_frames = 5;           // shorter tracks are dropped as noise
  double adjust_rate_hz = 10.0;       // frames the adjustment uses (the tracking uses every frame)
  double sigma_px = 1.0;              // point noise of the adjustment
  double robust_px = 2.0;             // Cauchy loss scale
  double gyro_noise_rad_s = 0.003;    // relative-rotation sigma = this x sqrt(dt) + 0.05 deg
  double gravity_sigma_deg = 2.0;     // the accelerometer's up direction per frame (walking accelerations)
  double accel_noise_m_s2 = 0.5;      // the accelerometer's acceleration in the levelled frame (tilt, lever arm)
  double still_start_s = 1.0;         // the walk's first second, held still, gives the gyro bias
  double height_tolerance = 0.15;     // a found cone's height within this fraction of an inventory height
  int min_frames = 30;                // a cone seen in fewer adjusted frames is not constrained
  double min_view_spread_deg = 90.0;  // ... nor one seen over a smaller arc of directions around it
  double outlier_px = 4.0;            // an observation off by more is an outlier
  double moved_fraction = 0.2;        // a cone with more outliers than this moved during the walk
  std::string Validate() const;       // "" or what is wrong, naming the field
};

struct SurveyedCone {
  rig_model::ConeSpec spec;                           // the inventory's cone at its surveyed position
  Eigen::Vector3d sigma_m = Eigen::Vector3d::Zero();  // 1-sigma per axis (the adjustment's covariance x correlation)
  double correlation_factor = 1.0;                    // its sightings' errors' integrated autocorrelation (bundle.cpp)
  int frames = 0;                                     // adjusted frames that saw it
  double view_spread_deg = 0.0;                       // arc of directions it was seen from
  double rms_px = 0.0;                                // its reprojection RMS
  double outlier_fraction = 0.0;
  double first_seen_s = 0.0, last_seen_s = 0.0;  // since the first frame
};

struct SurveyResult {
  bool ok = false;
  std::string error;                 // why not, naming the cones (inventory entries) concerned
  std::vector<SurveyedCone> cones;   // inventory order
  double reprojection_rms_px = 0.0;  // per coordinate, all observations
  int frames_adjusted = 0, observations = 0, tracks = 0;
  Eigen::Vector3d gyro_bias_rad_s = Eigen::Vector3d::Zero();  // IMU frame
  double base_offset_px = 0.0;     // the detected bases below the model's, along the cone's image axis
  double scale_sigma = 0.0;        // the layout's scale's 1-sigma (fraction), in every cone's sigma_m
  std::vector<std::string> notes;  // what the user should know (no still start, ...)
};

SurveyResult SurveyLayout(const SurveyInput& input, const Inventory& inventory, const SurveyConfig& config);

}  // namespace cone_survey
