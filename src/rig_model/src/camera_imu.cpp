#include "rig_model/camera_imu.h"

#include <cmath>

#include "pose_math/rotation.h"
#include "rig_model/strict_yaml.h"

namespace rig_model {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// A list of `n` finite numbers at where.key.
Eigen::VectorXd ReadVector(const StrictReader& r, const YAML::Node& map, const std::string& where,
                           const std::string& key, int n) {
  const YAML::Node v = map[key];
  const std::string field = FieldPath(where, key);
  if (!v) r.Fail(map, field, "is missing");
  if (!v.IsSequence() || static_cast<int>(v.size()) != n)
    r.Fail(v, field, "must be a list of " + std::to_string(n) + " numbers");
  Eigen::VectorXd out(n);
  for (int i = 0; i < n; ++i) {
    try {
      out[i] = v[i].as<double>();
    } catch (const YAML::Exception&) {
      r.Fail(v, field, "must be a list of " + std::to_string(n) + " numbers");
    }
    if (!std::isfinite(out[i])) r.Fail(v, field, "must be finite");
  }
  return out;
}

}  // namespace

Eigen::Matrix3d MountRotation(const Eigen::Vector3d& mount_error_rpy_deg) {
  // IMU x forward = camera z; IMU y left = camera -x; IMU z up = camera -y.
  Eigen::Matrix3d nominal;
  nominal << 0, -1, 0,  //
      0, 0, -1,         //
      1, 0, 0;
  const Eigen::Vector3d e = mount_error_rpy_deg * kDeg;  // fixed-axis roll, pitch, yaw = Rz Ry Rx (2.19)
  return nominal * pose_math::RotationFromEulerZyx(pose_math::EulerZyx{e.z(), e.y(), e.x(), false});
}

const std::vector<std::string>& CameraImuFileKeys() {
  static const std::vector<std::string> keys = {"parent_frame",
                                                "child_frame",
                                                "translation_m",
                                                "rotation_xyzw",
                                                "method",
                                                "rms_residual_deg",
                                                "euler_minimisation_rotation_xyzw",
                                                "euler_minimisation_rms_residual_deg",
                                                "svd_vs_euler_deg",
                                                "poses"};
  return keys;
}

CameraImuExtrinsics LoadCameraImuFile(const std::string& path) {
  const YAML::Node root = LoadYamlFile(path);
  const StrictReader r(path);
  r.CheckKeys(root, {"camera_imu"}, "");
  const YAML::Node c = root["camera_imu"];
  if (!c) r.Fail(root, "camera_imu", "is missing");
  r.CheckKeys(c, CameraImuFileKeys(), "camera_imu");
  CameraImuExtrinsics e;
  e.parent_frame = r.String(c, "camera_imu", "parent_frame", e.parent_frame);
  e.child_frame = r.String(c, "camera_imu", "child_frame", e.child_frame);
  if (e.parent_frame.empty()) r.Fail(c["parent_frame"], "camera_imu.parent_frame", "must not be empty");
  if (e.child_frame.empty()) r.Fail(c["child_frame"], "camera_imu.child_frame", "must not be empty");
  if (c["translation_m"]) e.p_imu_in_camera_m = ReadVector(r, c, "camera_imu", "translation_m", 3);
  if (e.p_imu_in_camera_m.norm() > kMaxLeverArmM) {
    r.Fail(c["translation_m"], "camera_imu.translation_m",
           "is the IMU's origin in the camera frame in metres; " + std::to_string(e.p_imu_in_camera_m.norm()) +
               " m is longer than 1 m: not a rig (centimetres?)");
  }
  const Eigen::VectorXd q = ReadVector(r, c, "camera_imu", "rotation_xyzw", 4);
  // The tolerance of camera_imu_static_tf.py: a zero or unnormalised quaternion is a broken file.
  if (std::abs(q.norm() - 1.0) > 1e-3) {
    r.Fail(c["rotation_xyzw"], "camera_imu.rotation_xyzw",
           "must be a unit quaternion [x, y, z, w] (norm " + std::to_string(q.norm()) + ")");
  }
  e.q_camera_imu = Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized();
  return e;
}

}  // namespace rig_model
