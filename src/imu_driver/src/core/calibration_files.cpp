#include "imu_driver/core/calibration_files.h"

#include <cmath>

#include "rig_model/strict_yaml.h"

namespace imu_driver {
namespace {

// `count` finite numbers at where.key.
Eigen::VectorXd Numbers(const rig_model::StrictReader& r, const YAML::Node& map, const std::string& where,
                        const std::string& key, int count) {
  const YAML::Node n = map[key];
  const std::string field = rig_model::FieldPath(where, key);
  const std::string must = "must be a list of " + std::to_string(count) + " finite numbers";
  if (!n.IsSequence() || static_cast<int>(n.size()) != count) r.Fail(n, field, must);
  Eigen::VectorXd v(count);
  for (int i = 0; i < count; ++i) {
    try {
      v(i) = n[i].as<double>();
    } catch (const YAML::Exception&) {
      r.Fail(n, field, must);
    }
  }
  if (!v.allFinite()) r.Fail(n, field, must);
  return v;
}

}  // namespace

const std::vector<std::string>& CameraImuKeys() {
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

const std::vector<std::string>& GyroCalibrationKeys() {
  static const std::vector<std::string> keys = {"gyro_bias_rad_s", "gyro_noise_sigma_rad_s", "gyro_calibration_source"};
  return keys;
}

CameraImuFile ReadCameraImuFile(const std::string& path) {
  const rig_model::StrictReader r(path);
  const YAML::Node root = rig_model::LoadYamlFile(path);
  r.CheckKeys(root, {"camera_imu"}, "");
  const YAML::Node c = root["camera_imu"];
  if (!c) r.Fail(root, "camera_imu", "is missing");
  r.CheckKeys(c, CameraImuKeys(), "camera_imu");
  CameraImuFile f;
  f.parent_frame = r.String(c, "camera_imu", "parent_frame", f.parent_frame);
  f.child_frame = r.String(c, "camera_imu", "child_frame", f.child_frame);
  if (f.parent_frame.empty()) r.Fail(c["parent_frame"], "camera_imu.parent_frame", "must not be empty");
  if (f.child_frame.empty()) r.Fail(c["child_frame"], "camera_imu.child_frame", "must not be empty");
  if (c["translation_m"]) f.translation_m = Numbers(r, c, "camera_imu", "translation_m", 3);
  if (!c["rotation_xyzw"]) r.Fail(c, "camera_imu.rotation_xyzw", "is missing");
  const Eigen::VectorXd q = Numbers(r, c, "camera_imu", "rotation_xyzw", 4);
  // The tolerance of camera_imu_static_tf.py: a zero or unnormalised quaternion is a broken file.
  if (std::abs(q.norm() - 1.0) > 1e-3) {
    r.Fail(c["rotation_xyzw"], "camera_imu.rotation_xyzw",
           "must be a unit quaternion [x, y, z, w] (norm " + std::to_string(q.norm()) + ")");
  }
  f.q_camera_imu = Eigen::Quaterniond(q(3), q(0), q(1), q(2)).normalized();
  return f;
}

GyroCalibrationFile ReadGyroCalibrationFile(const std::string& path) {
  const rig_model::StrictReader r(path);
  YAML::Node root = rig_model::LoadYamlFile(path);
  if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);  // comments only: nothing calibrated
  r.CheckKeys(root, GyroCalibrationKeys(), "");
  r.String(root, "", "gyro_calibration_source", "");
  GyroCalibrationFile f;
  if (root["gyro_bias_rad_s"]) f.gyro_bias_rad_s = Numbers(r, root, "", "gyro_bias_rad_s", 3);
  if (root["gyro_noise_sigma_rad_s"]) {
    f.gyro_noise_sigma_rad_s = Numbers(r, root, "", "gyro_noise_sigma_rad_s", 3);
    if (f.gyro_noise_sigma_rad_s->minCoeff() < 0.0) {
      r.Fail(root["gyro_noise_sigma_rad_s"], "gyro_noise_sigma_rad_s", "must be 3 finite numbers >= 0");
    }
  }
  return f;
}

}  // namespace imu_driver
