// Writes a scenario straight into a rosbag with the rosbag C++ API (no ROS
// master). Deterministic: the same scenario and seed give a byte-identical bag.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "rig_sim/ros/messages.h"
#include "rig_sim/scenario.h"
#include "rig_sim/sim_stream.h"

namespace rig_sim {

struct BagOptions {
  double start_time_s = 1700000000.0;  // bag time of scenario t = 0
  std::string compression = "none";    // none | lz4 | bz2
  StreamConfig stream;
  TopicNames topics;
  FrameNames frames;
  bool truth_tf = true;  // cones -> camera_optical_truth on /tf at the IMU rate
};

struct BagStats {
  uint64_t images = 0, imu = 0, truth = 0;
  double render_s = 0.0;  // time spent rendering (wall clock, for reports only)
};

// Returns false with a message on a bad option or an I/O error.
bool WriteScenarioBag(const Scenario& scenario, const BagOptions& options, const std::string& path, BagStats* stats,
                      std::string* error);

}  // namespace rig_sim
