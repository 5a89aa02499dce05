#include "rig_model/ros/imu_mount.h"

namespace rig_model {

std::optional<ImuMount> ImuMountCache::Lookup(const tf2_ros::Buffer& tf, const std::string& camera_frame,
                                              const std::string& imu_frame, double first_timeout_s, std::string* error,
                                              bool* fresh) {
  if (fresh) *fresh = false;
  if (imu_frame.empty()) {
    if (error) *error = "IMU message without frame_id (REP-145 needs it)";
    return std::nullopt;
  }
  if (imu_frame == camera_frame) return ImuMount{};
  const auto it = mounts_.find(imu_frame);
  if (it != mounts_.end()) return it->second;
  try {
    const bool first = tried_.insert(imu_frame).second;
    const auto t =
        tf.lookupTransform(camera_frame, imu_frame, ros::Time(0), ros::Duration(first ? first_timeout_s : 0.0));
    const auto& r = t.transform.rotation;
    const auto& p = t.transform.translation;
    ImuMount m{Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized(), Eigen::Vector3d(p.x, p.y, p.z)};
    if (fresh) *fresh = true;
    return mounts_[imu_frame] = m;
  } catch (const tf2::TransformException& e) {
    if (error) *error = "no tf " + camera_frame + " <- " + imu_frame + ": " + e.what();
    return std::nullopt;
  }
}

}  // namespace rig_model
