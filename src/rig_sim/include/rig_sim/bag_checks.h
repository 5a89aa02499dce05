// The bag validator's checks, on plain records extracted from a bag (the
// reader lives in ros/bag_reader). ROS-free so the rules are unit-tested on
// hand-made data. Every failure message names the topic, the time (seconds
// from the first message) and the limit that was broken.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rig_sim {

struct ValidateConfig {
  double imu_rate_hz = 100.0;    // expected; 0 skips the rate check
  double camera_rate_hz = 30.0;  // expected; 0 skips the rate check
  double min_truth_rate_hz = 100.0;
  double rate_tolerance = 0.05;  // relative, on the median period
  double max_gap_factor = 3.0;   // a gap above this many median periods fails
  double max_latency_s = 1.0;    // bag (receive) time minus header stamp
  double gravity_m_s2 = 9.81;
  double rest_accel_tolerance_m_s2 = 0.2;  // on the mean over a rest stretch
  double rest_gyro_max_rad_s = 0.05;       // mean over a rest stretch (turn-on bias included)
};

struct StampRecord {
  double stamp_s = 0.0;    // header stamp
  double receive_s = 0.0;  // bag time
};
struct ImuRecord : StampRecord {
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();
  double orientation_covariance0 = -1.0;
  std::string frame;
};
struct ImageRecord : StampRecord {
  uint32_t width = 0, height = 0, step = 0;
  std::string encoding, frame;
  size_t data_size = 0;
};
struct InfoRecord : StampRecord {
  uint32_t width = 0, height = 0;
  std::string frame, distortion_model;
  size_t d_size = 0;
  double fx = 0.0, fy = 0.0;
};
struct TruthRecord : StampRecord {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
};

struct BagContents {
  std::string imu_topic = "imu/data_raw", image_topic = "camera/image_raw";
  std::string info_topic = "camera/camera_info", truth_topic = "rig_sim/ground_truth";
  std::vector<ImuRecord> imu;
  std::vector<ImageRecord> images;
  std::vector<InfoRecord> infos;
  std::vector<TruthRecord> truth;
};

struct Check {
  std::string name;
  bool ok = true;
  std::string message;
};

struct ValidationReport {
  std::vector<Check> checks;
  bool ok() const;
  std::string Text() const;  // one line per check: "PASS name: message" / "FAIL ..."
};

ValidationReport ValidateContents(const BagContents& bag, const ValidateConfig& config);

}  // namespace rig_sim
