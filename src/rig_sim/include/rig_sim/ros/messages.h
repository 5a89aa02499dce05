// Core types -> ROS messages, shared by the bag writer and the live node.
#pragma once

#include <string>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include "rig_sim/scenario.h"
#include "rig_sim/sim_stream.h"

namespace rig_sim {

struct TopicNames {
  std::string image = "camera/image_raw";
  std::string camera_info = "camera/camera_info";
  std::string imu = "imu/data_raw";
  std::string truth = "rig_sim/ground_truth";       // PoseStamped, camera_optical in cones
  std::string imu_bias = "rig_sim/imu_bias_truth";  // Imu message carrying the true biases
  std::string markers = "rig_sim/cones";            // MarkerArray, for rviz
};

struct FrameNames {
  std::string cones = "cones";
  std::string camera = "camera_optical";
  std::string imu = "imu";
  // Truth lives on its own tf edge, never on the estimator's cones -> camera_optical.
  std::string camera_truth = "camera_optical_truth";
  std::string imu_truth = "imu_truth";
};

// Scenario time t_s after start_s, rounded to the nanosecond (so that equal
// times from different rates give equal stamps).
ros::Time StampAt(double start_s, double t_s);

sensor_msgs::CameraInfo MakeCameraInfo(const CameraConfig& camera, const ros::Time& stamp, const std::string& frame);
sensor_msgs::ImagePtr MakeEmptyImage(const CameraConfig& camera, const ros::Time& stamp, const std::string& frame);
// REP-145: an IMU message is stamped when its measurement applies. The core's sample stamped t_k
// covers (t_k - dt, t_k], so its message carries the interval's midpoint t_k - dt/2 (imu_driver stamps
// the Crista's samples the same way, and pose_ekf expects it).
ros::Time ImuMessageStamp(const ros::Time& interval_end, const ImuConfig& config);
sensor_msgs::Imu MakeImu(const ImuSample& s, const ImuConfig& config, const ros::Time& stamp, const std::string& frame);
sensor_msgs::Imu MakeImuBias(const ImuSample& s, const ros::Time& stamp, const std::string& frame);
geometry_msgs::PoseStamped MakeTruthPose(const TruePose& pose, const ros::Time& stamp, const std::string& frame);
geometry_msgs::TransformStamped MakeTruthTransform(const TruePose& pose, const ros::Time& stamp,
                                                   const FrameNames& frames);
// Static truth: camera_optical_truth -> imu_truth (the IMU mount).
tf2_msgs::TFMessage MakeStaticTruth(const ImuConfig& imu, const ros::Time& stamp, const FrameNames& frames);
visualization_msgs::MarkerArray MakeConeMarkers(const Scene& scene, const ros::Time& stamp, const std::string& frame);

}  // namespace rig_sim
