// Talking to a running cone_tracker nodelet from a rostest: publish frames and
// camera_info, read its /diagnostics status, poses and dynamic_reconfigure.
#pragma once

#include <functional>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>

#include "rig_model/camera_model.h"

namespace cone_tracker {

bool SpinUntil(const std::function<bool()>& done, double timeout_s);

// The camera_info of this camera (rig_model_ros, as rig_sim publishes it).
sensor_msgs::CameraInfo CameraInfo(const rig_model::CameraModel& camera);

// The nodelet's "cone_tracker: tracker" diagnostic status.
struct TrackerStatus {
  int level = -1;
  std::string message;
  std::map<std::string, std::string> values;
  double Value(const std::string& key) const;  // NaN when absent
};

class NodeletRig {
 public:
  NodeletRig();
  bool Connect();  // waits for the nodelet's subscriptions
  void PublishInfo(const sensor_msgs::CameraInfo& info);
  // Until the status counts at least `frames` frames (a fresh status, not an old one).
  bool WaitForFrames(double frames);
  // Was a pose published for the frame with this stamp? Call after WaitForFrames for that frame, with
  // the "poses published" count from before it: the nodelet's own count decides (no waiting for a pose
  // that might still come); when it went up, waits for the pose itself, which may trail /diagnostics.
  bool PoseOfFrame(const ros::Time& stamp, double poses_before);
  bool Reconfigure(const std::vector<std::pair<std::string, double>>& doubles);

  ros::NodeHandle nh;
  ros::Publisher image_pub, info_pub;
  TrackerStatus status;                           // "cone_tracker: tracker", the latest
  std::map<std::string, TrackerStatus> statuses;  // every status on /diagnostics by name, the latest
  std::set<uint64_t> pose_stamps;

 private:
  ros::Subscriber diag_sub_, pose_sub_;
};

}  // namespace cone_tracker
