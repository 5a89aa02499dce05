// A measuring nodelet loaded into the pipeline's manager: end-to-end latency (LatencyMatcher, steady
// clock), message counts per inter-nodelet topic, NaN checks on the EKF output and the manager's RSS
// (this process's /proc/self/status). Everything is written as JSON to ~output_file once a second, so
// a benchmark or test reads it after killing the launch without relying on a clean shutdown.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <tf2_msgs/TFMessage.h>
#include <pluginlib/class_list_macros.hpp>

#include "ar_bringup/latency_matcher.h"
#include "ar_bringup/probe_config.h"

namespace ar_bringup {
namespace {

double SteadyNow() { return ros::WallTime::now().toSec(); }  // CLOCK_MONOTONIC in roscpp

long ReadRssKb() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;
}

bool PoseFinite(const geometry_msgs::PoseWithCovarianceStamped& m) {
  const auto& p = m.pose.pose;
  bool ok = std::isfinite(p.position.x) && std::isfinite(p.position.y) && std::isfinite(p.position.z) &&
            std::isfinite(p.orientation.x) && std::isfinite(p.orientation.y) && std::isfinite(p.orientation.z) &&
            std::isfinite(p.orientation.w);
  for (double c : m.pose.covariance) ok = ok && std::isfinite(c);
  return ok;
}

}  // namespace

class LatencyProbeNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    try {
      config_ = LoadProbeConfig(pnh);
    } catch (const std::invalid_argument& e) {
      NODELET_FATAL("latency_probe: %s; not measuring", e.what());
      return;
    }
    // Large queues: the probe must not lose what it counts.
    image_sub_ = nh.subscribe("camera/image_raw", 100, &LatencyProbeNodelet::OnImage, this);
    pose_sub_ = nh.subscribe("cone_tracker/pose", 100, &LatencyProbeNodelet::OnTrackerPose, this);
    ekf_sub_ = nh.subscribe("pose_ekf/pose", 1000, &LatencyProbeNodelet::OnEkfPose, this);
    imu_sub_ = nh.subscribe("imu/data_raw", 1000, &LatencyProbeNodelet::OnImu, this);
    tf_sub_ = nh.subscribe("/tf", 1000, &LatencyProbeNodelet::OnTf, this);
    timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { Write(); });
  }

  // Callbacks run on any of the manager's worker threads: one mutex guards all the state.
  void OnImage(const sensor_msgs::ImageConstPtr& msg) {
    const double now = SteadyNow();
    std::lock_guard<std::mutex> lock(mutex_);
    ++images_;
    matcher_.OnImage(msg->header.stamp.toNSec(), now);
  }
  void OnTrackerPose(const geometry_msgs::PoseWithCovarianceStampedConstPtr& msg) {
    const double now = SteadyNow();
    std::lock_guard<std::mutex> lock(mutex_);
    ++tracker_poses_;
    matcher_.OnPose(msg->header.stamp.toNSec(), now);
  }
  void OnEkfPose(const geometry_msgs::PoseWithCovarianceStampedConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++ekf_poses_;
    if (!PoseFinite(*msg)) ++ekf_nan_;
  }
  void OnImu(const sensor_msgs::ImuConstPtr&) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++imu_;
  }
  void OnTf(const tf2_msgs::TFMessageConstPtr& msg) {
    const double now = SteadyNow();
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& t : msg->transforms) {
      if (t.header.frame_id != config_.fixed_frame || t.child_frame_id != config_.camera_frame) continue;
      ++tf_;
      matcher_.OnTf(t.header.stamp.toNSec(), now);
    }
  }

  void Write() {
    std::ostringstream out;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      rss_kb_.push_back(ReadRssKb());
      const LatencyStats e2e = Summarise(matcher_.end_to_end_ms());
      const LatencyStats trk = Summarise(matcher_.tracker_ms());
      out << "{\"sim_time_s\": " << std::fixed << ros::Time::now().toSec() << std::defaultfloat
          << ", \"images\": " << images_ << ", \"tracker_poses\": " << tracker_poses_
          << ", \"ekf_poses\": " << ekf_poses_ << ", \"ekf_nan\": " << ekf_nan_ << ", \"imu\": " << imu_
          << ", \"tf\": " << tf_ << ", \"unmatched_poses\": " << matcher_.unmatched_poses()
          << ",\n \"latency\": {\"count\": " << e2e.count << ", \"median_ms\": " << e2e.median_ms
          << ", \"p99_ms\": " << e2e.p99_ms << ", \"max_ms\": " << e2e.max_ms
          << "},\n \"tracker_latency\": {\"count\": " << trk.count << ", \"median_ms\": " << trk.median_ms
          << ", \"p99_ms\": " << trk.p99_ms << ", \"max_ms\": " << trk.max_ms << "},\n \"rss_kb\": [";
      for (size_t i = 0; i < rss_kb_.size(); ++i) out << (i ? ", " : "") << rss_kb_[i];
      out << "]}\n";
    }
    if (config_.output_file.empty()) return;
    const std::string tmp = config_.output_file + ".tmp";
    {
      std::ofstream f(tmp);
      f << out.str();
      if (!f) {
        NODELET_WARN_THROTTLE(10.0, "latency_probe: cannot write %s", tmp.c_str());
        return;
      }
    }
    if (std::rename(tmp.c_str(), config_.output_file.c_str()) != 0)
      NODELET_WARN_THROTTLE(10.0, "latency_probe: cannot rename %s to %s", tmp.c_str(), config_.output_file.c_str());
  }

  ProbeConfig config_;
  ros::Subscriber image_sub_, pose_sub_, ekf_sub_, imu_sub_, tf_sub_;
  ros::WallTimer timer_;
  std::mutex mutex_;
  LatencyMatcher matcher_;
  size_t images_ = 0, tracker_poses_ = 0, ekf_poses_ = 0, ekf_nan_ = 0, imu_ = 0, tf_ = 0;
  std::vector<long> rss_kb_;
};

}  // namespace ar_bringup

PLUGINLIB_EXPORT_CLASS(ar_bringup::LatencyProbeNodelet, nodelet::Nodelet)
