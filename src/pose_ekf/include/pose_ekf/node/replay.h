// ekf_replay: runs the filter over a bag as fast as possible and writes the
// camera-in-cones trajectory in TUM format (t x y z qx qy qz qw).
#pragma once

#include <iosfwd>
#include <string>

#include "pose_ekf/node/node_config.h"

namespace pose_ekf {

struct ReplayOptions {
  std::string bag_path;
  std::string output_path;
  std::string camera_topic = "cone_tracker/pose";
  std::string imu_topic = "imu/data_raw";
  std::string observations_topic = "cone_tracker/observations";  // per-cone updates (config.layout_file)
  NodeConfig config;
  // Optional: one line per cone observation message (stamp, cone ids, what became of it, the lone-cone
  // ambiguity statistics, the position sigma after it, the fused cones' joint NIS: 4 degrees of freedom a cone), for
  // looking at re-acquisitions frame by frame and at how the cones' covariances compare with their innovations.
  std::string cone_log_path;
  // Optional: one line per pose written, its stamp, the diagonal of its ROS 6x6 covariance (x y z rx ry rz) and,
  // when they are states, the gyro and accelerometer biases (camera axes) with their sigmas: with a truth at hand,
  // how consistent the filter is, e.g. in camera outages (README, "camera outages").
  std::string covariance_path;
  // Optional: one line per observed cone, its residuals against the truth (TruthResiduals::Header), on bags that
  // carry truth_topic; their means and spreads go to the log.
  std::string truth_residuals_path;
  std::string truth_topic = "rig_sim/ground_truth";  // geometry_msgs/PoseStamped, camera_optical in cones
  // Optional, a what-if on such bags: "peak", "base" or "both" of every observed cone replaced by its pixels at the
  // true pose (TruthResiduals::TruthPixels; the mid by their midpoint), the covariances kept: the filter with that
  // part of the tracker made exact. Frames without truth stay as recorded.
  std::string truth_points;
};

struct ReplaySummary {
  size_t camera_messages = 0, imu_messages = 0, poses_written = 0, observation_messages = 0;
  size_t camera_gated = 0, reinits = 0;  // the chi-square gate on camera poses
  bool orientation_only = false;         // no camera messages: gyro + gravity updates
  std::string imu_rotation_source;
};

// Throws std::runtime_error on unreadable bags or unwritable output.
ReplaySummary RunReplay(const ReplayOptions& options, std::ostream& log);

}  // namespace pose_ekf
