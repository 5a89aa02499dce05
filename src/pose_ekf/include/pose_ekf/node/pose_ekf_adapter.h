// Messages <-> core: turns cone_tracker/pose and imu/data_raw into core
// measurements and the filter state into pose, odometry and tf messages. No
// NodeHandle, publisher or tf listener here, so a replay test can drive it
// without a ROS master; the nodelet adds those.
#pragma once

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

 private:
  bool FillOutputs(const EkfCore& filter, AdapterOutputs* out) const;

  NodeConfig config_;
  MeasurementBuffer buffer_;
  AddResult Count(ConversionResult r);
  uint64_t invalid_rejected_ = 0, nan_rejected_ = 0;
  uint64_t camera_rejected_ = 0, camera_quaternions_normalized_ = 0;
};

}  // namespace pose_ekf
