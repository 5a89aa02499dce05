#include "bag_replay.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <geometry_msgs/PoseStamped.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <Eigen/Cholesky>

#include "pose_math/rotation.h"
#include "rig_model/ros/conversions.h"

namespace cone_tracker {
namespace {

pose_math::Pose FromMsg(const geometry_msgs::Pose& p) {
  pose_math::Pose T = rig_model::FromPoseMsg(p);
  T.q = T.q.normalized();
  return T;
}

bool InView(const sensor_msgs::CameraInfo& info, const pose_math::Pose& T_cones_camera,
            const std::vector<ConeModel>& layout, double margin) {
  const pose_math::Pose T_camera_cones = pose_math::Invert(T_cones_camera);
  for (const ConeModel& c : layout) {
    for (const Eigen::Vector3d& p : {c.base_m, Eigen::Vector3d(c.base_m + Eigen::Vector3d(0, 0, c.height_m))}) {
      const Eigen::Vector3d pc = pose_math::Transform(T_camera_cones, p);
      if (pc.z() < 0.1) return false;
      const double u = info.K[0] * pc.x() / pc.z() + info.K[2], v = info.K[4] * pc.y() / pc.z() + info.K[5];
      if (u < margin || v < margin || u > info.width - 1 - margin || v > info.height - 1 - margin) return false;
    }
  }
  return true;
}

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(p * double(v.size())))];
}

}  // namespace

std::vector<BagFrame> ReadBag(const std::string& path, const std::vector<ConeModel>& layout, double margin_px) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  // One pass: the bag is bz2-compressed and every chunk holds truth samples.
  std::map<uint64_t, pose_math::Pose> truth;
  std::vector<std::pair<sensor_msgs::CameraInfoConstPtr, sensor_msgs::ImageConstPtr>> images;
  sensor_msgs::CameraInfoConstPtr info;
  const std::vector<std::string> topics{"camera/camera_info", "camera/image_raw", "rig_sim/ground_truth"};
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(topics))) {
    if (auto p = m.instantiate<geometry_msgs::PoseStamped>()) truth[p->header.stamp.toNSec()] = FromMsg(p->pose);
    if (auto i = m.instantiate<sensor_msgs::CameraInfo>()) info = i;
    auto image = m.instantiate<sensor_msgs::Image>();
    if (image && info) images.emplace_back(info, image);
  }
  std::vector<BagFrame> frames;
  for (const auto& [i, image] : images) {
    const auto t = truth.find(image->header.stamp.toNSec());
    if (t == truth.end()) continue;
    frames.push_back({i, image, t->second, InView(*i, t->second, layout, margin_px)});
  }
  return frames;
}

Accuracy Evaluate(const std::vector<BagFrame>& frames,
                  const std::map<uint64_t, geometry_msgs::PoseWithCovarianceStamped>& poses) {
  Accuracy a;
  std::vector<double> dp, dr, nees;
  for (const BagFrame& f : frames) {
    a.frames_in_view += f.all_cones_in_view;
    const auto it = poses.find(f.image->header.stamp.toNSec());
    if (it == poses.end()) continue;
    ++a.poses;
    a.poses_in_view += f.all_cones_in_view;
    const pose_math::Pose est = FromMsg(it->second.pose.pose);
    const pose_math::Pose& truth = f.truth_T_cones_camera;
    // ROS convention (pose_math/covariance.h): position, then the fixed-axis
    // rotation in the parent frame, R_est = Exp(dtheta) R_truth.
    Eigen::Matrix<double, 6, 1> e;
    e.head<3>() = est.t - truth.t;
    const Eigen::Matrix3d dR = pose_math::RotationFromQuat(est.q) * pose_math::RotationFromQuat(truth.q).transpose();
    const Eigen::AngleAxisd aa(dR);
    e.tail<3>() = aa.angle() * aa.axis();
    dp.push_back(e.head<3>().norm());
    dr.push_back(aa.angle() * 180.0 / M_PI);
    Eigen::Matrix<double, 6, 6> cov;
    for (int i = 0; i < 36; ++i) cov(i / 6, i % 6) = it->second.pose.covariance[size_t(i)];
    const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(cov);
    if (!cov.isApprox(cov.transpose(), 1e-9) || llt.info() != Eigen::Success) {
      ++a.covariance_not_pd;
      continue;
    }
    nees.push_back(e.dot(llt.solve(e)));
  }
  auto rms = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x * x;
    return v.empty() ? 0.0 : std::sqrt(s / double(v.size()));
  };
  a.position_rms_m = rms(dp), a.rotation_rms_deg = rms(dr);
  a.position_max_m = dp.empty() ? 0 : *std::max_element(dp.begin(), dp.end());
  a.rotation_max_deg = dr.empty() ? 0 : *std::max_element(dr.begin(), dr.end());
  a.position_p95_m = Percentile(dp, 0.95), a.rotation_p95_deg = Percentile(dr, 0.95);
  for (double x : nees) a.nees_mean += x / double(nees.size());
  a.nees_p95 = Percentile(nees, 0.95);
  return a;
}

std::string Accuracy::Summary() const {
  char s[512];
  std::snprintf(s, sizeof s,
                "poses %d (%d of %d frames with every cone in view); position RMS %.4f m, p95 %.4f m, max %.4f m; "
                "rotation RMS %.3f deg, p95 %.3f deg, max %.3f deg; NEES mean %.2f, p95 %.2f (6 when consistent); "
                "covariances not positive definite %d",
                poses, poses_in_view, frames_in_view, position_rms_m, position_p95_m, position_max_m, rotation_rms_deg,
                rotation_p95_deg, rotation_max_deg, nees_mean, nees_p95, covariance_not_pd);
  return s;
}

}  // namespace cone_tracker
