// aravis_camera/ZeroCopyProbe: a consumer for checking the driver in place.
// Subscribes to `image` and counts the frames whose data is the driver's own
// pool memory (FramePool::IsPoolMemory), i.e. frames that arrived without a
// copy, and the latency from the frame's stamp to this callback. Publishes a
// one-line summary on ~stats (std_msgs/String) every second, latency over
// the latest 3000 frames. Use it with
// ~stamp_source:=completion on the camera to measure completion-to-callback
// latency.
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/String.h>
#include <pluginlib/class_list_macros.hpp>

#include <algorithm>
#include <cstdio>
#include <deque>
#include <vector>

#include "aravis_camera/device/frame_pool.h"

namespace aravis_camera {

class ZeroCopyProbe : public nodelet::Nodelet {
 private:
  void onInit() override {
    stats_pub_ = getPrivateNodeHandle().advertise<std_msgs::String>("stats", 1, true);
    sub_ = getNodeHandle().subscribe("image", 5, &ZeroCopyProbe::OnImage, this);
    timer_ = getNodeHandle().createWallTimer(ros::WallDuration(1.0), &ZeroCopyProbe::Report, this);
  }

  void OnImage(const sensor_msgs::ImageConstPtr& image) {
    const double latency_ms = (ros::Time::now() - image->header.stamp).toSec() * 1e3;
    ++frames_;
    if (FramePool::IsPoolMemory(image->data.data())) ++zero_copy_frames_;
    latencies_ms_.push_back(latency_ms);
    if (latencies_ms_.size() > kWindow) latencies_ms_.pop_front();
  }

  void Report(const ros::WallTimerEvent&) {
    std::vector<double> l(latencies_ms_.begin(), latencies_ms_.end());
    double median = 0.0, p99 = 0.0;
    if (!l.empty()) {
      std::sort(l.begin(), l.end());
      median = l[l.size() / 2];
      p99 = l[std::min(l.size() - 1, static_cast<size_t>(0.99 * l.size()))];
    }
    char buf[160];
    std::snprintf(buf, sizeof(buf), "frames=%lu zero_copy=%lu latency_median_ms=%.3f latency_p99_ms=%.3f",
                  static_cast<unsigned long>(frames_), static_cast<unsigned long>(zero_copy_frames_), median, p99);
    std_msgs::String msg;
    msg.data = buf;
    stats_pub_.publish(msg);
  }

  ros::Subscriber sub_;
  ros::Publisher stats_pub_;
  ros::WallTimer timer_;
  uint64_t frames_ = 0, zero_copy_frames_ = 0;
  static constexpr size_t kWindow = 3000;  // the latest frames, 100 s at 30 Hz
  std::deque<double> latencies_ms_;        // single-threaded callbacks: no lock needed
};

}  // namespace aravis_camera

PLUGINLIB_EXPORT_CLASS(aravis_camera::ZeroCopyProbe, nodelet::Nodelet)
