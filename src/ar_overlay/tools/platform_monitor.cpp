// ar_overlay_platform_monitor: the overlay test platform's measurement (7.2)
// on a live overlay stream. Subscribes to ar_overlay/image and
// camera/camera_info, measures every frame (platform_alignment.h) and appends
// one CSV row per red dot to ~output:
//   stamp_s,red_x_px,red_y_px,error_x_px,error_y_px,m_per_px
// Frames with no measurable dot are counted, and the totals logged at exit.
#include <cv_bridge/cv_bridge.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <cstdio>
#include <memory>

#include "ar_overlay/core/platform_alignment.h"
#include "ar_overlay/node/ros_config.h"

namespace {

class Monitor {
 public:
  Monitor(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
    std::string path;
    pnh.param("output", path, std::string("platform_errors.csv"));
    pnh.param("spacing_m", config_.spacing_m, config_.spacing_m);
    file_.reset(std::fopen(path.c_str(), "w"));
    if (!file_) throw std::runtime_error("cannot write " + path);
    std::fprintf(file_.get(), "stamp_s,red_x_px,red_y_px,error_x_px,error_y_px,m_per_px\n");
    info_sub_ = nh.subscribe("camera/camera_info", 2, &Monitor::OnInfo, this);
    image_sub_ = nh.subscribe("ar_overlay/image", 30, &Monitor::OnImage, this);
  }
  ~Monitor() { ROS_INFO("platform monitor: %d frames, %d with dots measured, %d dots", frames_, measured_, dots_); }

 private:
  void OnInfo(const sensor_msgs::CameraInfoConstPtr& info) { info_ = info; }
  void OnImage(const sensor_msgs::ImageConstPtr& msg) {
    ++frames_;
    if (!info_) return;
    try {
      const cv_bridge::CvImageConstPtr bgr = cv_bridge::toCvShare(msg, "bgr8");
      const auto errors = ar_overlay::MeasureAlignment(bgr->image, ar_overlay::FromCameraInfo(*info_), config_);
      measured_ += !errors.empty();
      for (const auto& e : errors) {
        std::fprintf(file_.get(), "%.6f,%.3f,%.3f,%.4f,%.4f,%.6g\n", msg->header.stamp.toSec(), e.red_px.x, e.red_px.y,
                     e.error_px.x, e.error_px.y, e.m_per_px);
        ++dots_;
      }
      std::fflush(file_.get());
    } catch (const std::exception& e) {
      ROS_WARN_THROTTLE(5.0, "platform monitor: %s", e.what());
    }
  }

  struct Close {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  ar_overlay::AlignmentConfig config_;
  std::unique_ptr<std::FILE, Close> file_;
  ros::Subscriber info_sub_, image_sub_;
  sensor_msgs::CameraInfoConstPtr info_;
  int frames_ = 0, measured_ = 0, dots_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "platform_monitor");
  ros::NodeHandle nh, pnh("~");
  try {
    Monitor monitor(nh, pnh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("platform monitor: %s", e.what());
    return 1;
  }
  return 0;
}
