#include "imu_driver/node/ros_adapter.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "imu_driver/core/calibration_files.h"
#include "imu_driver/core/serial_port.h"
#include "rig_model/ros/param_table_ros.h"
#include "rig_model/strict_yaml.h"

namespace imu_driver {
namespace {

[[noreturn]] void Refuse(const ros::NodeHandle& pnh, const std::string& name, const std::string& why) {
  throw std::invalid_argument("parameter " + pnh.resolveName(name) + ": " + why);
}

void RequirePositive(const ros::NodeHandle& pnh, const std::string& name, double v) {
  if (!(v > 0.0) || !std::isfinite(v)) Refuse(pnh, name, "must be a positive number, got " + std::to_string(v));
}

// The lists the table cannot hold (3-vectors); a value that is not a list of numbers is refused.
Eigen::Vector3d Vector3Param(const ros::NodeHandle& pnh, const std::string& name, const Eigen::Vector3d& def,
                             bool non_negative) {
  std::vector<double> v;
  if (!pnh.hasParam(name)) return def;
  if (!pnh.getParam(name, v)) Refuse(pnh, name, "must be a list of 3 numbers");
  if (v.size() != 3) Refuse(pnh, name, "must be a list of 3 numbers, got " + std::to_string(v.size()));
  const Eigen::Vector3d e(v[0], v[1], v[2]);
  if (!e.allFinite() || (non_negative && e.minCoeff() < 0.0)) {
    Refuse(pnh, name, non_negative ? "must be 3 finite numbers >= 0" : "must be 3 finite numbers");
  }
  return e;
}

// Names under ~ that are not in the table: the lists read by Vector3Param and from ~camera_imu/
// (the 3.2.2 calibration YAML's keys, when it is rosparam-loaded), and the calibration YAML's
// gyro_calibration_source (a note, accepted and not used).
std::vector<std::string> ListNames() {
  std::vector<std::string> names = {"gyro_bias_rad_s", "gyro_noise_sigma_rad_s", "accel_noise_sigma_m_s2",
                                    "gyro_calibration_source"};
  for (const std::string& key : CameraImuKeys()) names.push_back("camera_imu/" + key);
  return names;
}

// The keys of ~config_file's mapping at `ns` ("" for the top level; "time_sync"), from the
// parameter names: a nested name "time_sync/window_s" is "time_sync" at the top, "window_s" inside.
std::vector<std::string> FileKeys(const std::string& ns) {
  std::vector<std::string> names = DriverParamTable().Names(), keys;
  const std::vector<std::string> lists = ListNames();
  names.insert(names.end(), lists.begin(), lists.end());
  for (const std::string& name : names) {
    const std::string key = ns.empty()                                      ? name.substr(0, name.find('/'))
                            : name.compare(0, ns.size() + 1, ns + "/") == 0 ? name.substr(ns.size() + 1)
                                                                            : "";
    if (!key.empty() && std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
  }
  return keys;
}

// ~config_file: set by imu_driver.launch to the YAML it loaded here (config/imu_driver.yaml), so
// that its keys are checked with their lines and unknown-parameter errors name it.
void CheckConfigFile(const std::string& path) {
  try {
    const rig_model::StrictReader r(path);
    const YAML::Node root = rig_model::LoadYamlFile(path);
    r.CheckKeys(root, FileKeys(""), "");
    if (root["time_sync"]) r.CheckKeys(root["time_sync"], FileKeys("time_sync"), "time_sync");
    if (root["camera_imu"]) r.CheckKeys(root["camera_imu"], CameraImuKeys(), "camera_imu");
  } catch (const rig_model::FileError& e) {
    throw std::invalid_argument(e.what());
  }
}

// The calibration files named by ~gyro_calibration_file and ~camera_imu_file (read here, not by
// roslaunch, so that every error names the file). Their values override parameters of the same name.
void ReadCalibrationFiles(const DriverParams& p, DriverConfig* c) {
  try {
    if (!p.gyro_calibration_file.empty()) {
      const GyroCalibrationFile g = ReadGyroCalibrationFile(p.gyro_calibration_file);
      if (g.gyro_bias_rad_s) {
        c->gyro_bias_rad_s = *g.gyro_bias_rad_s;
        c->gyro_bias_calibrated = true;
      }
      if (g.gyro_noise_sigma_rad_s) c->gyro_noise_sigma_rad_s = *g.gyro_noise_sigma_rad_s;
    }
    if (!p.camera_imu_file.empty()) c->q_camera_imu = ReadCameraImuFile(p.camera_imu_file).q_camera_imu;
  } catch (const rig_model::FileError& e) {
    throw std::invalid_argument(e.what());
  }
}

}  // namespace

const rig_model::ParamTable<DriverParams>& DriverParamTable() {
  using P = DriverParams;
  static const rig_model::ParamTable<P> table =
      rig_model::ParamTable<P>()
          .Add("config_file", [](P& p) -> std::string& { return p.config_file; })
          .Add("gyro_calibration_file", [](P& p) -> std::string& { return p.gyro_calibration_file; })
          .Add("camera_imu_file", [](P& p) -> std::string& { return p.camera_imu_file; })
          .Add("port", [](P& p) -> std::string& { return p.config.reader.port; })
          .Add("baud", [](P& p) -> int& { return p.config.reader.baud; })
          .Add("frame_id", [](P& p) -> std::string& { return p.config.frame_id; })
          .Add("rate_hz", [](P& p) -> double& { return p.config.reader.stream.rate_hz; })
          .Add("stamp_at_interval_midpoint", [](P& p) -> bool& { return p.config.stamp_at_interval_midpoint; })
          .Add("retry_initial_s", [](P& p) -> double& { return p.config.reader.retry_initial_s; })
          .Add("retry_max_s", [](P& p) -> double& { return p.config.reader.retry_max_s; })
          .AddEnum("time_source", [](P& p) -> int& { return p.time_source; }, {"sequence", "pps"})
          .Add("time_sync/slack_ppm", [](P& p) -> double& { return p.config.reader.stream.time_sync.slack_ppm; })
          .Add("time_sync/window_s", [](P& p) -> double& { return p.config.reader.stream.time_sync.window_s; })
          .Add("time_sync/max_skew_ppm", [](P& p) -> double& { return p.config.reader.stream.time_sync.max_skew_ppm; })
          .Add("time_sync/jump_threshold_s",
               [](P& p) -> double& { return p.config.reader.stream.time_sync.jump_threshold_s; })
          .Add("subtract_gyro_bias", [](P& p) -> bool& { return p.config.subtract_gyro_bias; })
          .Add("publish_in_camera_frame", [](P& p) -> bool& { return p.config.publish_in_camera_frame; })
          .Add("camera_frame_id", [](P& p) -> std::string& { return p.config.camera_frame_id; })
          .Add("calibration_duration_s", [](P& p) -> double& { return p.config.calibration_duration_s; })
          .Add("calibrate_on_start", [](P& p) -> bool& { return p.config.calibrate_on_start; })
          .Add("calibration_output_file", [](P& p) -> std::string& { return p.config.calibration_output_file; })
          .Add("stale_after_s", [](P& p) -> double& { return p.config.stale_after_s; })
          .Add("rate_tolerance", [](P& p) -> double& { return p.config.rate_tolerance; });
  return table;
}

DriverConfig LoadConfig(const ros::NodeHandle& pnh) {
  DriverParams p;
  std::string file;
  if (pnh.getParam("config_file", file) && !file.empty()) CheckConfigFile(file);  // its lines first
  try {
    rig_model::LoadParams(pnh, DriverParamTable(), &p, ListNames());
  } catch (const std::invalid_argument& e) {
    if (file.empty()) throw;
    throw std::invalid_argument(std::string(e.what()) + " (parameters loaded from " + file + ")");
  }
  DriverConfig& c = p.config;
  SerialReaderConfig& r = c.reader;
  if (r.port.empty()) Refuse(pnh, "port", "must not be empty");
  if (BaudToSpeed(r.baud) == 0) Refuse(pnh, "baud", "unsupported rate " + std::to_string(r.baud));
  if (c.frame_id.empty()) Refuse(pnh, "frame_id", "must not be empty");
  for (const auto& [name, v] : {std::pair<const char*, double>{"rate_hz", r.stream.rate_hz},
                                {"retry_initial_s", r.retry_initial_s},
                                {"retry_max_s", r.retry_max_s},
                                {"time_sync/slack_ppm", r.stream.time_sync.slack_ppm},
                                {"time_sync/window_s", r.stream.time_sync.window_s},
                                {"time_sync/max_skew_ppm", r.stream.time_sync.max_skew_ppm},
                                {"time_sync/jump_threshold_s", r.stream.time_sync.jump_threshold_s},
                                {"calibration_duration_s", c.calibration_duration_s},
                                {"stale_after_s", c.stale_after_s},
                                {"rate_tolerance", c.rate_tolerance}})
    RequirePositive(pnh, name, v);
  if (r.retry_max_s < r.retry_initial_s) Refuse(pnh, "retry_max_s", "must be >= retry_initial_s");
  r.stream.time_source = p.time_source == 1 ? StreamConfig::TimeSource::kPps : StreamConfig::TimeSource::kSequence;

  c.gyro_bias_calibrated = pnh.hasParam("gyro_bias_rad_s");
  c.gyro_bias_rad_s = Vector3Param(pnh, "gyro_bias_rad_s", c.gyro_bias_rad_s, false);
  c.gyro_noise_sigma_rad_s = Vector3Param(pnh, "gyro_noise_sigma_rad_s", c.gyro_noise_sigma_rad_s, true);
  c.accel_noise_sigma_m_s2 = Vector3Param(pnh, "accel_noise_sigma_m_s2", c.accel_noise_sigma_m_s2, true);

  std::vector<double> q;
  const bool camera_imu_file = pnh.hasParam("camera_imu_file");  // read by ReadCalibrationFiles
  if (!camera_imu_file && pnh.hasParam("camera_imu/rotation_xyzw")) {
    if (!pnh.getParam("camera_imu/rotation_xyzw", q)) q.clear();
    const Eigen::Vector4d v = q.size() == 4 ? Eigen::Vector4d(q[0], q[1], q[2], q[3]) : Eigen::Vector4d::Zero();
    if (!v.allFinite() || v.norm() < 0.5 || v.norm() > 1.5) {
      Refuse(pnh, "camera_imu/rotation_xyzw", "must be a unit quaternion [x, y, z, w]");
    }
    c.q_camera_imu = Eigen::Quaterniond(v(3), v(0), v(1), v(2)).normalized();
  } else if (!camera_imu_file && c.publish_in_camera_frame) {
    Refuse(pnh, "camera_imu_file",
           "needed by publish_in_camera_frame: the 3.2.2 calibration YAML (or set ~camera_imu/rotation_xyzw)");
  }
  ReadCalibrationFiles(p, &c);
  return c;
}

void FillImuMessage(const ImuSample& s, const DriverConfig& config, const GyroCalibration& gyro,
                    sensor_msgs::Imu* msg) {
  const double shift_s = config.stamp_at_interval_midpoint ? 0.5 / config.reader.stream.rate_hz : 0.0;
  // Never below 0: ros::Time throws on negative times (a sample read before /clock started is at 0).
  msg->header.stamp.fromSec(std::max(0.0, s.stamp_s - shift_s));
  Eigen::Vector3d omega(s.si.omega_imu_rad_s[0], s.si.omega_imu_rad_s[1], s.si.omega_imu_rad_s[2]);
  Eigen::Vector3d accel(s.si.accel_imu_m_s2[0], s.si.accel_imu_m_s2[1], s.si.accel_imu_m_s2[2]);
  if (config.subtract_gyro_bias) omega -= gyro.bias_rad_s;  // (3.27) with v_gyro left in
  Eigen::Matrix3d cov_omega = gyro.sigma_rad_s.cwiseAbs2().asDiagonal();
  Eigen::Matrix3d cov_accel = config.accel_noise_sigma_m_s2.cwiseAbs2().asDiagonal();
  msg->header.frame_id = config.frame_id;
  if (config.publish_in_camera_frame) {
    const Eigen::Matrix3d R = config.q_camera_imu.toRotationMatrix();
    omega = R * omega;  // (3.26), coincident origins
    accel = R * accel;
    cov_omega = R * cov_omega * R.transpose();
    cov_accel = R * cov_accel * R.transpose();
    msg->header.frame_id = config.camera_frame_id;
  }
  msg->orientation.x = msg->orientation.y = msg->orientation.z = 0.0;
  msg->orientation.w = 1.0;
  msg->orientation_covariance.fill(0.0);
  msg->orientation_covariance[0] = -1.0;  // REP-145: no orientation estimate
  msg->angular_velocity.x = omega.x();
  msg->angular_velocity.y = omega.y();
  msg->angular_velocity.z = omega.z();
  msg->linear_acceleration.x = accel.x();
  msg->linear_acceleration.y = accel.y();
  msg->linear_acceleration.z = accel.z();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      msg->angular_velocity_covariance[3 * i + j] = cov_omega(i, j);
      msg->linear_acceleration_covariance[3 * i + j] = cov_accel(i, j);
    }
  }
}

std::string GyroCalibrationYaml(const GyroBiasResult& r) {
  std::ostringstream y;
  y << std::setprecision(9);
  auto vec = [&y](const Eigen::Vector3d& v) { y << "[" << v(0) << ", " << v(1) << ", " << v(2) << "]\n"; };
  y << "# Static gyro bias calibration (thesis 3.2.1), written by imu_driver's imu/calibrate.\n";
  y << "# " << r.message << "\n";
  y << "gyro_bias_rad_s: ";
  vec(r.bias_rad_s);
  y << "gyro_noise_sigma_rad_s: ";
  vec(r.sigma_rad_s);
  return y.str();
}

}  // namespace imu_driver
