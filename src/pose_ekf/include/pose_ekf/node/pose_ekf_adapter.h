// Messages <-> core: turns cone_tracker/pose and imu/data_raw into core
// measurements and the filter state into pose, odometry and tf messages. No
// NodeHandle, publisher or tf listener here, so a replay test can drive it
// without a ROS master; the nodelet adds those.
#pragma once

#include <cone_tracker/ConeObservations.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/Imu.h>

#include <Eigen/Geometry>
#include <string>

#include "pose_ekf/core/measurement_buffer.h"
#include "pose_ekf/node/node_config.h"

namespace pose_ekf {

enum class ConversionResult { kOk, kNonFinite, kInvalid };

// The nodelet's camera subscription (before remapping), named in the reasons a pose is refused.
constexpr const char* kCameraTopic = "cone_tracker/pose";
// The nodelet's cone observation subscription (before remapping), named in the reasons a frame or a
// cone is refused.
constexpr const char* kObservationsTopic = "cone_tracker/observations";
// A camera quaternion with | |q|² - 1 | above this is counted as far from unit
// (tf2 refuses such a quaternion). Any non-zero finite quaternion is normalised
// and used: the direction is the rotation, and the gate judges it.
constexpr double kQuaternionNorm2Tolerance = 0.01;
bool QuaternionFarFromUnit(const geometry_msgs::Quaternion& q);

// Conversions. Anything but kOk comes with a reason in *why.
ConversionResult CameraFromMsg(const geometry_msgs::PoseWithCovarianceStamped& msg, const std::string& cones_frame,
                               CameraMeasurement* out, std::string* why);
// q_camera_imu rotates IMU-frame vectors into the camera frame (3.2.2, from tf);
// p_imu_in_camera_m is the same tf's translation, the lever arm (ImuMeasurement).
// REP-145: a covariance whose first element is -1 means the field is absent;
// an all-zero covariance means unknown (the configured sigma is used).
ConversionResult ImuFromMsg(const sensor_msgs::Imu& msg, const Eigen::Quaterniond& q_camera_imu, ImuMeasurement* out,
                            std::string* why, const Eigen::Vector3d& p_imu_in_camera_m = Eigen::Vector3d::Zero());
// The refusal of an absurd lever arm (longer than kMaxLeverArmM): empty when usable, otherwise a
// message naming the tf and the calibration field it comes from.
std::string CheckLeverArm(const Eigen::Vector3d& p_imu_in_camera_m, const std::string& camera_frame,
                          const std::string& imu_frame);

// cone_tracker/observations -> ConeFrame. The whole message is refused (kInvalid or kNonFinite) for a
// wrong header.frame_id (not camera_frame), a non-finite stamp, fx or fy not positive and finite,
// cx or cy not finite, or no layout (layout_cones empty). A single cone with a non-finite pixel
// (kNonFinite), an id not in the layout, or a covariance that is not a finite symmetric positive
// definite 2x2 (kInvalid) is left out and counted in *cones_refused; the others are kept, and *why
// names the first problem (topic, field and cone). kOk with no cones left means nothing to fuse.
ConversionResult ConeFrameFromMsg(const cone_tracker::ConeObservations& msg, const std::string& camera_frame,
                                  const std::vector<ConeGeometry>& layout, ConeFrame* out, std::string* why,
                                  int* cones_nan, int* cones_invalid);

struct AdapterOutputs {
  geometry_msgs::PoseWithCovarianceStamped pose;
  nav_msgs::Odometry odometry;
  geometry_msgs::TransformStamped tf;
};

class PoseEkfAdapter {
 public:
  explicit PoseEkfAdapter(const NodeConfig& config);

  // Each returns what the buffer did (kRejectedNonFinite or kRejectedInvalid when
  // the message never reached it); *why says why a message was refused.
  AddResult HandleCamera(const geometry_msgs::PoseWithCovarianceStamped& msg, std::string* why);
  AddResult HandleImu(const sensor_msgs::Imu& msg, const Eigen::Quaterniond& q_camera_imu, std::string* why,
                      const Eigen::Vector3d& p_imu_in_camera_m = Eigen::Vector3d::Zero());
  // cone_tracker/observations: ConeFrameFromMsg, then MeasurementBuffer::AddCones. A message whose
  // every cone was refused returns the refusal; a stamp older than the buffer is kDroppedLate.
  AddResult HandleObservations(const cone_tracker::ConeObservations& msg, std::string* why);

  // The current estimate as messages, stamped at the filter time. False before
  // initialisation.
  bool MakeOutputs(AdapterOutputs* out) const;
  // The estimate predicted forward to stamp_s without changing the filter (fixed-rate output).
  bool MakePredictedOutputs(double stamp_s, AdapterOutputs* out) const;

  void Reconfigure(const EkfConfig& ekf);  // throws std::invalid_argument
  void Reset() { buffer_.Reset(); }
  const MeasurementBuffer& buffer() const { return buffer_; }
  MeasurementBuffer& buffer() { return buffer_; }
  const NodeConfig& config() const { return config_; }
  // Refused before the buffer: wrong frame, bad covariance, no data; and non-finite
  // values the conversion could not carry. Add to the buffer's counters for totals.
  uint64_t invalid_rejected() const { return invalid_rejected_; }
  uint64_t nan_rejected() const { return nan_rejected_; }
  // Camera poses refused for a zero or non-finite quaternion, a non-finite
  // position or covariance, a bad covariance diagonal or a wrong frame (part of
  // the two above), and those whose quaternion was far from unit (normalised, used).
  uint64_t camera_rejected() const { return camera_rejected_; }
  uint64_t camera_quaternions_normalized() const { return camera_quaternions_normalized_; }
  // cone_tracker/observations refused whole (frame, stamp, intrinsics, no layout), and single cones
  // refused (non-finite pixel, unknown id, bad covariance); also in the NaN/invalid totals above.
  uint64_t observations_rejected() const { return observations_rejected_; }
  uint64_t cones_refused_nan() const { return cones_refused_nan_; }
  uint64_t cones_refused_invalid() const { return cones_refused_invalid_; }

 private:
  bool FillOutputs(const EkfCore& filter, AdapterOutputs* out) const;

  NodeConfig config_;
  MeasurementBuffer buffer_;
  AddResult Count(ConversionResult r);
  uint64_t invalid_rejected_ = 0, nan_rejected_ = 0;
  uint64_t camera_rejected_ = 0, camera_quaternions_normalized_ = 0;
  uint64_t observations_rejected_ = 0, cones_refused_nan_ = 0, cones_refused_invalid_ = 0;
};

}  // namespace pose_ekf
