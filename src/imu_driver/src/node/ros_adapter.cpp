#include "imu_driver/node/ros_adapter.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "imu_driver/core/serial_port.h"
#include "imu_driver/core/calibration_files.h"
#include "rig_model/ros/params.h"
#include "rig_model/strict_yaml.h"

namespace imu_driver {
namespace {

[[noreturn]] void Refuse(const ros::NodeHandle& pnh, const std::string& name, const std::string& why) {
  throw std::invalid_argument("parameter " + pnh.resolveName(name) + ": " + why);
}

double PositiveParam(const ros::NodeHandle& pnh, const std::string& name, double def) {
  double v = def;
  pnh.param(name, v, def);
  if (!(v > 0.0) || !std::isfinite(v)) Refuse(pnh, name, "must be a positive number, got " + std::to_string(v));
  return v;
}

Eigen::Vector3d Vector3Param(const ros::NodeHandle& pnh, const std::string& name, const Eigen::Vector3d& def,
                             bool non_negative) {
  std::vector<double> v;
  if (!pnh.getParam(name, v)) return def;
  if (v.size() != 3) Refuse(pnh, name, "must be a list of 3 numbers, got " + std::to_string(v.size()));
  const Eigen::Vector3d e(v[0], v[1], v[2]);
  if (!e.allFinite() || (non_negative && e.minCoeff() < 0.0)) {
    Refuse(pnh, name, non_negative ? "must be 3 finite numbers >= 0" : "must be 3 finite numbers");
  }
  return e;
}

// Every parameter LoadConfig reads (one level deep), plus diagnostic_updater's own.
const std::vector<std::string> kParamNames = {"config_file",
                                              "port",
                                              "baud",
                                              "frame_id",
                                              "rate_hz",
                                              "stamp_at_interval_midpoint",
                                              "retry_initial_s",
                                              "retry_max_s",
                                              "time_source",
                                              "time_sync",
                                              "gyro_calibration_file",
                                              "gyro_calibration_source",
                                              "gyro_bias_rad_s",
                                              "subtract_gyro_bias",
                                              "gyro_noise_sigma_rad_s",
                                              "accel_noise_sigma_m_s2",
                                              "publish_in_camera_frame",
                                              "camera_frame_id",
                                              "camera_imu_file",
                                              "camera_imu",
                                              "calibration_duration_s",
                                              "calibrate_on_start",
                                              "calibration_output_file",
                                              "stale_after_s",
                                              "rate_tolerance",
                                              "diagnostic_period"};
const std::vector<std::string> kTimeSyncNames = {"slack_ppm", "window_s", "max_skew_ppm", "jump_threshold_s"};

// CheckParamNames one namespace down, naming parameters from the private namespace (~time_sync/x).
void CheckNestedNames(const ros::NodeHandle& pnh, const std::string& ns, const std::vector<std::string>& known) {
  try {
    rig_model::CheckParamNames(ros::NodeHandle(pnh, ns), known);
  } catch (const std::invalid_argument& e) {
    std::string m = e.what();
    for (size_t p = m.find('~'); p != std::string::npos; p = m.find('~', p + ns.size() + 2)) m.insert(p + 1, ns + "/");
    throw std::invalid_argument(m);
  }
}

// ~config_file: set by imu_driver.launch to the YAML it loaded here (config/imu_driver.yaml), so
// that its keys are checked with their lines and unknown-parameter errors name it.
void CheckConfigFile(const std::string& path) {
  try {
    const rig_model::StrictReader r(path);
    const YAML::Node root = rig_model::LoadYamlFile(path);
    r.CheckKeys(root, kParamNames, "");
    if (root["time_sync"]) r.CheckKeys(root["time_sync"], kTimeSyncNames, "time_sync");
    if (root["camera_imu"]) r.CheckKeys(root["camera_imu"], CameraImuKeys(), "camera_imu");
  } catch (const rig_model::FileError& e) {
    throw std::invalid_argument(e.what());
  }
}

// The calibration files named by ~gyro_calibration_file and ~camera_imu_file (read here, not by
// roslaunch, so that every error names the file). Their values override parameters of the same name.
void ReadCalibrationFiles(const ros::NodeHandle& pnh, DriverConfig* c) {
  std::string path;
  pnh.param<std::string>("gyro_calibration_file", path, "");
  try {
    if (!path.empty()) {
      const GyroCalibrationFile g = ReadGyroCalibrationFile(path);
      if (g.gyro_bias_rad_s) {
        c->gyro_bias_rad_s = *g.gyro_bias_rad_s;
        c->gyro_bias_calibrated = true;
      }
      if (g.gyro_noise_sigma_rad_s) c->gyro_noise_sigma_rad_s = *g.gyro_noise_sigma_rad_s;
    }
    pnh.param<std::string>("camera_imu_file", path, "");
    if (!path.empty()) c->q_camera_imu = ReadCameraImuFile(path).q_camera_imu;
  } catch (const rig_model::FileError& e) {
    throw std::invalid_argument(e.what());
  }
}

}  // namespace

DriverConfig LoadConfig(const ros::NodeHandle& pnh) {
  std::string file;
  pnh.param<std::string>("config_file", file, "");
  if (!file.empty()) CheckConfigFile(file);
  try {
    rig_model::CheckParamNames(pnh, kParamNames);
    CheckNestedNames(pnh, "time_sync", kTimeSyncNames);
    CheckNestedNames(pnh, "camera_imu", CameraImuKeys());
  } catch (const std::invalid_argument& e) {
    if (file.empty()) throw;
    throw std::invalid_argument(std::string(e.what()) + " (parameters loaded from " + file + ")");
  }
  DriverConfig c;
  SerialReaderConfig& r = c.reader;
  pnh.param<std::string>("port", r.port, "/dev/ttyUSB0");
  if (r.port.empty()) Refuse(pnh, "port", "must not be empty");
  pnh.param("baud", r.baud, 115200);
  if (BaudToSpeed(r.baud) == 0) Refuse(pnh, "baud", "unsupported rate " + std::to_string(r.baud));
  pnh.param<std::string>("frame_id", c.frame_id, "imu");
  if (c.frame_id.empty()) Refuse(pnh, "frame_id", "must not be empty");
  r.stream.rate_hz = PositiveParam(pnh, "rate_hz", 100.0);
  pnh.param("stamp_at_interval_midpoint", c.stamp_at_interval_midpoint, true);
  r.retry_initial_s = PositiveParam(pnh, "retry_initial_s", 0.1);
  r.retry_max_s = PositiveParam(pnh, "retry_max_s", 2.0);
  if (r.retry_max_s < r.retry_initial_s) Refuse(pnh, "retry_max_s", "must be >= retry_initial_s");
  std::string time_source;
  pnh.param<std::string>("time_source", time_source, "sequence");
  if (time_source == "pps") {
    r.stream.time_source = StreamConfig::TimeSource::kPps;
  } else if (time_source != "sequence") {
    Refuse(pnh, "time_source", "must be 'sequence' or 'pps', got '" + time_source + "'");
  }
  TimeSyncConfig& ts = r.stream.time_sync;
  ts.slack_ppm = PositiveParam(pnh, "time_sync/slack_ppm", ts.slack_ppm);
  ts.window_s = PositiveParam(pnh, "time_sync/window_s", ts.window_s);
  ts.max_skew_ppm = PositiveParam(pnh, "time_sync/max_skew_ppm", ts.max_skew_ppm);
  ts.jump_threshold_s = PositiveParam(pnh, "time_sync/jump_threshold_s", ts.jump_threshold_s);

  c.gyro_bias_calibrated = pnh.hasParam("gyro_bias_rad_s");
  c.gyro_bias_rad_s = Vector3Param(pnh, "gyro_bias_rad_s", c.gyro_bias_rad_s, false);
  pnh.param("subtract_gyro_bias", c.subtract_gyro_bias, true);
  c.gyro_noise_sigma_rad_s = Vector3Param(pnh, "gyro_noise_sigma_rad_s", c.gyro_noise_sigma_rad_s, true);
  c.accel_noise_sigma_m_s2 = Vector3Param(pnh, "accel_noise_sigma_m_s2", c.accel_noise_sigma_m_s2, true);

  pnh.param("publish_in_camera_frame", c.publish_in_camera_frame, false);
  pnh.param<std::string>("camera_frame_id", c.camera_frame_id, "camera_optical");
  std::vector<double> q;
  const bool camera_imu_file = pnh.hasParam("camera_imu_file");  // read by ReadCalibrationFiles
  if (!camera_imu_file && pnh.getParam("camera_imu/rotation_xyzw", q)) {
    const Eigen::Vector4d v = q.size() == 4 ? Eigen::Vector4d(q[0], q[1], q[2], q[3]) : Eigen::Vector4d::Zero();
    if (!v.allFinite() || v.norm() < 0.5 || v.norm() > 1.5) {
      Refuse(pnh, "camera_imu/rotation_xyzw", "must be a unit quaternion [x, y, z, w]");
    }
    c.q_camera_imu = Eigen::Quaterniond(v(3), v(0), v(1), v(2)).normalized();
  } else if (!camera_imu_file && c.publish_in_camera_frame) {
    Refuse(pnh, "camera_imu_file",
           "needed by publish_in_camera_frame: the 3.2.2 calibration YAML (or set ~camera_imu/rotation_xyzw)");
  }
  ReadCalibrationFiles(pnh, &c);

  c.calibration_duration_s = PositiveParam(pnh, "calibration_duration_s", 5.0);
  pnh.param("calibrate_on_start", c.calibrate_on_start, false);
  pnh.param<std::string>("calibration_output_file", c.calibration_output_file, "");
  c.stale_after_s = PositiveParam(pnh, "stale_after_s", 0.5);
  c.rate_tolerance = PositiveParam(pnh, "rate_tolerance", 0.1);
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
