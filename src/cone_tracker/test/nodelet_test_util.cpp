#include "nodelet_test_util.h"

#include <cmath>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <sensor_msgs/Image.h>

#include "rig_model/ros/conversions.h"

namespace cone_tracker {

bool SpinUntil(const std::function<bool()>& done, double timeout_s) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (ros::ok() && ros::WallTime::now() < end) {
    ros::spinOnce();
    if (done()) return true;
    ros::WallDuration(0.002).sleep();
  }
  return done();
}

sensor_msgs::CameraInfo CameraInfo(const rig_model::CameraModel& c) {
  return rig_model::ToCameraInfo(c, ros::Time(), "camera_optical");
}

double TrackerStatus::Value(const std::string& key) const {
  const auto it = values.find(key);
  return it == values.end() ? NAN : std::stod(it->second);
}

NodeletRig::NodeletRig() {
  image_pub = nh.advertise<sensor_msgs::Image>("camera/image_raw", 5);
  info_pub = nh.advertise<sensor_msgs::CameraInfo>("camera/camera_info", 1, /*latch=*/true);
  diag_sub_ = nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 50, [this](const auto& m) {
    for (const auto& s : m->status) {
      TrackerStatus t;
      t.level = s.level, t.message = s.message;
      for (const auto& kv : s.values) t.values[kv.key] = kv.value;
      statuses[s.name] = t;
      if (s.name == "cone_tracker: tracker") status = t;
    }
  });
  pose_sub_ = nh.subscribe<geometry_msgs::PoseWithCovarianceStamped>(
      "cone_tracker/pose", 50, [this](const auto& m) { pose_stamps.insert(m->header.stamp.toNSec()); });
}

bool NodeletRig::Connect() {
  return SpinUntil(
      [&] {
        return image_pub.getNumSubscribers() > 0 && info_pub.getNumSubscribers() > 0 &&
               diag_sub_.getNumPublishers() > 0;
      },
      60.0);
}

void NodeletRig::PublishInfo(const sensor_msgs::CameraInfo& info) {
  info_pub.publish(info);
  // Usually delivered before the next frame; a frame that overtakes it (another connection) is
  // counted by the nodelet as judged with the previous camera_info, and the tests send it again.
  SpinUntil([] { return false; }, 0.5);
}

bool NodeletRig::WaitForFrames(double frames) {
  status = TrackerStatus();
  return SpinUntil([&] { return status.Value("frames") >= frames; }, 30.0);
}

bool NodeletRig::PoseOfFrame(const ros::Time& stamp, double poses_before) {
  const double poses_after = status.Value("poses published");
  if (!(poses_after > poses_before)) return false;  // NaN (no status) counts as no pose
  return SpinUntil([&] { return pose_stamps.count(stamp.toNSec()) > 0; }, 60.0);
}

bool NodeletRig::Reconfigure(const std::vector<std::pair<std::string, double>>& doubles) {
  dynamic_reconfigure::Reconfigure srv;
  for (const auto& [name, value] : doubles) {
    dynamic_reconfigure::DoubleParameter p;
    p.name = name, p.value = value;
    srv.request.config.doubles.push_back(p);
  }
  if (!ros::service::waitForService("cone_tracker/set_parameters", ros::Duration(10.0))) return false;
  if (!ros::service::call("cone_tracker/set_parameters", srv)) return false;
  for (const auto& [name, value] : doubles) {
    bool found = false;
    for (const auto& p : srv.response.config.doubles)
      found = found || (p.name == name && std::abs(p.value - value) < 1e-9);
    if (!found) return false;
  }
  return true;
}

}  // namespace cone_tracker
