// The camera–IMU extrinsics (3.2.2): the rotation that takes IMU-frame vectors into camera_optical
// and the lever arm, the IMU's origin in camera_optical. The static tf camera_optical -> imu carries
// both (DESIGN.md). ROS-free.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rig_model {

struct CameraImuExtrinsics {
  std::string parent_frame = "camera_optical";
  std::string child_frame = "imu";
  Eigen::Quaterniond q_camera_imu = Eigen::Quaterniond::Identity();  // v_camera = R(q) v_imu
  Eigen::Vector3d p_imu_in_camera_m = Eigen::Vector3d::Zero();       // the lever arm

  Eigen::Matrix3d R_camera_imu() const { return q_camera_imu.toRotationMatrix(); }
};

// The rig's mount: an IMU with x forward, y left, z up (REP-103 body axes) on a camera looking
// forward (IMU x = camera z, IMU y = camera -x, IMU z = camera -y), tilted by a small mounting error
// given as fixed-axis roll, pitch, yaw in degrees (Rz Ry Rx, 2.19).
Eigen::Matrix3d MountRotation(const Eigen::Vector3d& mount_error_rpy_deg);

// A lever arm longer than this is refused (pose_ekf and camera_imu_static_tf.py refuse it too).
constexpr double kMaxLeverArmM = 1.0;

// Reads calibrate_camera_imu's YAML (imu_driver/config/camera_imu.yaml):
//   camera_imu: {parent_frame, child_frame, translation_m: [x, y, z], rotation_xyzw: [x, y, z, w]}
// strictly: unknown keys, a translation longer than kMaxLeverArmM, a missing rotation or a quaternion whose norm is not
// 1 (to 1e-3) throw FileError naming the file, line and field. The quaternion is normalised.
CameraImuExtrinsics LoadCameraImuFile(const std::string& path);
// The keys under `camera_imu:` (calibrate_camera_imu writes them all; the first four are the
// extrinsics, the rest its report, read by people).
const std::vector<std::string>& CameraImuFileKeys();

}  // namespace rig_model
