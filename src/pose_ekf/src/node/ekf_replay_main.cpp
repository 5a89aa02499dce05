// rosrun pose_ekf ekf_replay --bag IN.bag [--config FILE] --output traj.txt
//   [--camera-topic cone_tracker/pose] [--imu-topic imu/data_raw] [--cone-log FILE] [--covariance FILE]
//   [--truth-residuals FILE] [--truth-points peak|base|both]
#include <cstring>
#include <iostream>
#include <string>

#include "pose_ekf/node/replay.h"

int main(int argc, char** argv) {
  pose_ekf::ReplayOptions o;
  std::string config_path;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--bag")
      o.bag_path = value;
    else if (key == "--output")
      o.output_path = value;
    else if (key == "--config")
      config_path = value;
    else if (key == "--camera-topic")
      o.camera_topic = value;
    else if (key == "--imu-topic")
      o.imu_topic = value;
    else if (key == "--cone-log")
      o.cone_log_path = value;
    else if (key == "--covariance")
      o.covariance_path = value;
    else if (key == "--truth-residuals")
      o.truth_residuals_path = value;
    else if (key == "--truth-points")
      o.truth_points = value;
    else {
      std::cerr << "ekf_replay: unknown option " << key << "\n";
      return 2;
    }
  }
  if (o.bag_path.empty() || o.output_path.empty() || argc % 2 == 0) {
    std::cerr << "usage: ekf_replay --bag IN.bag [--config FILE.yaml] --output traj.txt "
                 "[--camera-topic T] [--imu-topic T] [--cone-log FILE] [--covariance FILE] [--truth-residuals FILE]\n"
                 "  [--truth-points peak|base|both]\n";
    return 2;
  }
  try {
    if (!config_path.empty()) o.config = pose_ekf::LoadConfigFile(config_path);
    pose_ekf::RunReplay(o, std::cerr);
  } catch (const std::exception& e) {
    const std::string what = e.what();
    // rosbag reports a bag cut short (recorder killed, partial copy) only as a failed read.
    const bool short_read = what.find("wanted") != std::string::npos || what.find("unindexed") != std::string::npos ||
                            what.find("Bag unindexed") != std::string::npos;
    std::cerr << "ekf_replay: " << what
              << (short_read ? "; the bag looks truncated: try `rosbag reindex " + o.bag_path + "`" : "") << "\n";
    return 1;
  }
  return 0;
}
