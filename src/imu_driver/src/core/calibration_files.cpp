#include "imu_driver/core/calibration_files.h"

#include <cmath>

#include "rig_model/camera_imu.h"
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

const std::vector<std::string>& CameraImuKeys() { return rig_model::CameraImuFileKeys(); }

const std::vector<std::string>& GyroCalibrationKeys() {
  static const std::vector<std::string> keys = {"gyro_bias_rad_s", "gyro_noise_sigma_rad_s", "gyro_calibration_source"};
  return keys;
}

CameraImuFile ReadCameraImuFile(const std::string& path) {
  const rig_model::CameraImuExtrinsics e = rig_model::LoadCameraImuFile(path);
  CameraImuFile f;
  f.parent_frame = e.parent_frame;
  f.child_frame = e.child_frame;
  f.translation_m = e.p_imu_in_camera_m;
  f.q_camera_imu = e.q_camera_imu;
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
