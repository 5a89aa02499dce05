// The cone_tracker adapter: sensor_msgs in, pose and detection messages out,
// around the ROS-free core (Segmenter, EstimateConePose). No publishers and no
// master needed, so tests can feed it from a bag deterministically; the
// nodelet adds subscriptions, tf, publishing and diagnostics.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "cone_tracker/ConeDetections.h"
#include "cone_tracker/ConeObservations.h"
#include "cone_tracker/node/node_config.h"
#include "cone_tracker/pose/associate.h"
#include "cone_tracker/vision/cone_pose.h"
#include "cone_tracker/vision/segmenter.h"

namespace cone_tracker {

enum class FrameStatus {
  kPose,                 // a pose passed every gate
  kNoCameraInfo,         // no camera_info received yet
  kBadCameraInfo,        // the latest camera_info is invalid (NaN, zero focal length, ...)
  kBadImage,             // empty, too small, inconsistent step or size, unreadable
  kUnsupportedEncoding,  // not rgb8, bgr8 or bayer_*8
  kSizeMismatch,         // image size differs from camera_info's
  kNoCones,              // no blob passed the segmentation gates
  kTooFewCones,          // 1-2 cones, or fewer than 3 matching the prediction
  kSolverFailed,
  kRejectedChi2,       // 6.4.1
  kRejectedMotion,     // 6.4.2
  kRejectedAmbiguous,  // large layout, no prediction: another assignment of the cones passed 6.4.1 too
};
const char* ToString(FrameStatus s);

struct FrameResult {
  FrameStatus status = FrameStatus::kBadImage;
  std::string message;  // why there is no pose; empty with a pose
  // Null when the image could not be segmented (bad image, encoding, camera_info).
  ConeDetections::Ptr detections;
  geometry_msgs::PoseWithCovarianceStamped::Ptr pose;  // null: no pose for this frame
  // Every associated cone's points and covariances; null when no cone was
  // associated (none seen, or no prediction and no pose: start-up).
  ConeObservations::Ptr observations;
  AssociationResult association;   // through the prediction (empty without one)
  std::string observation_source;  // "pose" (3.1.6's correspondence), "prediction" or "" (none)
  SegmentationResult segmentation;
  ConePoseResult cone_pose;
  std::string prediction_source = "none";  // tf, last_pose, reacquire, two_cones_gravity or none
  bool time_jumped_back = false;           // the stamp went back: the last pose was cleared
};

struct TrackerCounters {
  uint64_t frames = 0, poses = 0;
  uint64_t no_camera_info = 0, bad_camera_info_frames = 0, bad_camera_info_msgs = 0;
  uint64_t bad_image = 0, unsupported_encoding = 0, size_mismatch = 0;
  uint64_t no_cones = 0, too_few_cones = 0, solver_failed = 0, rejected_chi2 = 0, rejected_motion = 0;
  uint64_t rejected_ambiguous = 0;  // kRejectedAmbiguous
  uint64_t time_jumps = 0;
  uint64_t reacquisitions = 0;  // frames where a lost track re-initialised after its prediction failed
  uint64_t tf_overruled = 0;    // frames predicted from the own re-acquired track, tf contradicting it (Prediction)
  // The two-cone start (two_cone_pose.h): poses, frames it refused, frames it could not try (no gravity).
  uint64_t two_cone_poses = 0, two_cone_refused = 0, two_cone_no_gravity = 0;
  uint64_t cones_found_sum = 0;  // accepted blobs over segmented frames
  uint64_t segmented_frames = 0;
  // cone_tracker/observations
  uint64_t observation_msgs = 0, observed_cones_sum = 0;
  std::map<int, uint64_t> observation_msgs_by_cones;  // associated cones per message -> messages
  uint64_t association_ambiguous = 0;                 // detections left out: two layout cones fitted nearly as well
  uint64_t association_filter_covariance = 0;  // associations spread by pose_ekf's covariance (not the drift model)
  uint64_t association_conflicts = 0;          // frames whose prediction was not trusted (AssociationResult::conflict)
  uint64_t association_disagreements = 0;      // detections the prediction gave another cone than the accepted pose
  uint64_t unobserved_no_prediction = 0;       // frames with cones but neither a pose nor a prediction
  std::map<std::string, uint64_t> blobs_rejected_by_gate;  // segmentation gate name -> blobs
};

class TrackerAdapter {
 public:
  // Throws std::invalid_argument on a bad config or layout.
  TrackerAdapter(const NodeConfig& config, const std::vector<ConeModel>& layout);

  // Keeps the latest camera_info. Returns false with a message when K or D is
  // unusable; frames then give kBadCameraInfo until a valid one arrives.
  bool SetCameraInfo(const sensor_msgs::CameraInfo& info, std::string* error);
  // One frame. tf_T_cones_camera: the prediction from tf (pose_ekf), if any; tf_cov_ros: its covariance
  // as pose_ekf/pose publishes it (ROS order x y z rx ry rz, rotations about the axes of `cones`), if any;
  // up_camera: "up" in the camera at the image stamp (GravityWindow), for the two-cone start, if any.
  FrameResult Process(const sensor_msgs::ImageConstPtr& image, const std::optional<pose_math::Pose>& tf_T_cones_camera,
                      const std::optional<pose_math::Matrix6d>& tf_cov_ros = std::nullopt,
                      const std::optional<Eigen::Vector3d>& up_camera = std::nullopt);
  // dynamic_reconfigure: the colour table is rebuilt when the HSI bounds
  // change. Throws std::invalid_argument (config unchanged) on bad values.
  void Reconfigure(const SegmenterConfig& segmenter, const ConePoseConfig& pose, const DebugImageConfig& debug);
  // Forget the last pose (time jump, reset).
  void ClearTrack();

  const NodeConfig& config() const { return config_; }
  const std::vector<ConeModel>& layout() const { return layout_; }
  const TrackerCounters& counters() const { return counters_; }
  const Segmenter& segmenter() const { return detector_.segmenter(); }
  bool has_camera_info() const { return has_camera_info_; }
  bool camera_info_valid() const { return camera_valid_; }
  const std::string& camera_info_error() const { return camera_error_; }

 private:
  FrameResult Fail(FrameStatus status, const std::string& message);
  std::optional<pose_math::Pose> Prediction(const ros::Time& stamp,
                                            const std::optional<pose_math::Pose>& tf_T_cones_camera,
                                            std::string* source);
  // track_lost: no pose for reacquire_after_s, so a failed prediction re-initialises.
  void FillPose(const sensor_msgs::Image& image, const std::optional<pose_math::Pose>& T_cones_camera_pred,
                bool track_lost, const std::optional<Eigen::Vector3d>& up_camera, FrameResult* r);
  // cone_tracker/observations: the pose's correspondence when it passed the
  // gates, else the association through the prediction.
  // pred_cov_ros: the prediction's covariance (pose_ekf's), else the drift model below.
  void FillObservations(const sensor_msgs::Image& image, const std::optional<pose_math::Pose>& T_cones_camera_pred,
                        const std::optional<pose_math::Matrix6d>& pred_cov_ros, double since_tracked_s, FrameResult* r);

  NodeConfig config_;
  std::vector<ConeModel> layout_;
  ConeDetector detector_;  // the segmentation, or the learned detector (~detector)
  CameraModel camera_;
  int camera_width_ = 0, camera_height_ = 0;
  bool has_camera_info_ = false, camera_valid_ = false;
  std::string camera_error_;
  std::optional<pose_math::Pose> last_T_cones_camera_;
  ros::Time last_pose_stamp_, last_image_stamp_;
  ros::Time track_start_stamp_;  // first frame since the last ClearTrack (reacquire_after_s)
  ros::Time tracked_stamp_;      // last frame with a pose or two associated cones (prediction_drift_m_s)
  // The last pose descends from a re-acquisition (solved from the cones alone, tf having matched none of them): it
  // overrules tf while tf contradicts it (Prediction).
  bool own_track_ = false;
  TrackerCounters counters_;
};

// Names of the set bits of PoseGateBits (SegmentationGateNames: GateBits).
std::vector<std::string> PoseGateNames(uint32_t bits);

}  // namespace cone_tracker
