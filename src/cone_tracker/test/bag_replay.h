// Shared by the replay tests: a rig_sim bag in memory (camera frames with
// their camera_info, the ground truth) and the accuracy figures of a set of
// published poses against it.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "cone_tracker/vision/cone_pose.h"
#include "pose_math/pose.h"

namespace cone_tracker {

struct BagFrame {
  sensor_msgs::CameraInfoConstPtr info;  // the latest camera_info at or before the image
  sensor_msgs::ImageConstPtr image;
  pose_math::Pose truth_T_cones_camera;
  bool all_cones_in_view = false;  // every cone's peak and base at least margin px inside the image
};

// Frames of camera/image_raw with rig_sim/ground_truth at their stamps.
std::vector<BagFrame> ReadBag(const std::string& path, const std::vector<ConeModel>& layout, double margin_px);

struct Accuracy {
  int poses = 0, frames_in_view = 0, poses_in_view = 0;
  double position_rms_m = 0, position_max_m = 0, rotation_rms_deg = 0, rotation_max_deg = 0;
  double position_p95_m = 0, rotation_p95_deg = 0;
  double nees_mean = 0;  // 6-dof, ROS covariance; 6 when consistent
  double nees_p95 = 0;
  int covariance_not_pd = 0;  // poses whose 6x6 is not symmetric positive definite
  std::string Summary() const;
};

// poses: by image stamp (ns).
Accuracy Evaluate(const std::vector<BagFrame>& frames,
                  const std::map<uint64_t, geometry_msgs::PoseWithCovarianceStamped>& poses);

}  // namespace cone_tracker
