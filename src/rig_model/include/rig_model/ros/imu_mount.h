// The camera <- IMU mount (3.2.2) as tf carries it: the static transform the rig description publishes from
// the calibration (camera_imu.rotation, .translation_m), looked up once per IMU frame. One reader for every
// nodelet that turns IMU samples into the camera frame (pose_ekf: gyro, accelerometer and lever arm;
// cone_tracker: gravity for the two-cone start).
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>

#include <tf2_ros/buffer.h>
#include <Eigen/Geometry>

namespace rig_model {

struct ImuMount {
  Eigen::Quaterniond q_camera_imu = Eigen::Quaterniond::Identity();  // v_camera = q_camera_imu * v_imu
  Eigen::Vector3d p_imu_in_camera_m = Eigen::Vector3d::Zero();       // the lever arm
};

class ImuMountCache {
 public:
  // imu_frame's mount in camera_frame: the cached one, the identity when the two frames are the same, else
  // tf's latest. Only the first lookup of a frame waits (up to first_timeout_s): a missing tf must not stall
  // every 100 Hz sample, and tf2's wait runs on ros::Time, which stands still with /clock. None, with *error
  // ("IMU message without frame_id (REP-145 needs it)", "no tf camera <- imu: ..."), when there is none yet.
  // *fresh (optional): this call looked it up.
  std::optional<ImuMount> Lookup(const tf2_ros::Buffer& tf, const std::string& camera_frame,
                                 const std::string& imu_frame, double first_timeout_s, std::string* error,
                                 bool* fresh = nullptr);
  // Forget the mounts (time jumped back, tf cleared).
  void Clear() { mounts_.clear(); }

 private:
  std::map<std::string, ImuMount> mounts_;
  std::set<std::string> tried_;  // IMU frames looked up once (with the timeout)
};

}  // namespace rig_model
