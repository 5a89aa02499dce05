#include "rig_model/ros/conversions.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "pose_math/covariance.h"

namespace rig_model {
namespace {

using RowMajor6d = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;

geometry_msgs::Quaternion QuatMsg(const pose_math::Quat& q) {
  geometry_msgs::Quaternion m;
  m.w = q[0], m.x = q[1], m.y = q[2], m.z = q[3];
  return m;
}

pose_math::Quat FromQuatMsg(const geometry_msgs::Quaternion& m) { return pose_math::Quat(m.w, m.x, m.y, m.z); }

}  // namespace

geometry_msgs::Pose ToPoseMsg(const pose_math::Pose& T) {
  geometry_msgs::Pose m;
  m.position.x = T.t.x(), m.position.y = T.t.y(), m.position.z = T.t.z();
  m.orientation = QuatMsg(T.q);
  return m;
}

pose_math::Pose FromPoseMsg(const geometry_msgs::Pose& m) {
  pose_math::Pose T;
  T.q = FromQuatMsg(m.orientation);
  T.t = Eigen::Vector3d(m.position.x, m.position.y, m.position.z);
  return T;
}

geometry_msgs::Transform ToTransformMsg(const pose_math::Pose& T) {
  geometry_msgs::Transform m;
  m.translation.x = T.t.x(), m.translation.y = T.t.y(), m.translation.z = T.t.z();
  m.rotation = QuatMsg(T.q);
  return m;
}

pose_math::Pose FromTransformMsg(const geometry_msgs::Transform& m) {
  pose_math::Pose T;
  T.q = FromQuatMsg(m.rotation);
  T.t = Eigen::Vector3d(m.translation.x, m.translation.y, m.translation.z);
  return T;
}

geometry_msgs::TransformStamped ToTransformStamped(const pose_math::Pose& T, const ros::Time& stamp,
                                                   const std::string& parent, const std::string& child) {
  geometry_msgs::TransformStamped m;
  m.header.stamp = stamp;
  m.header.frame_id = parent;
  m.child_frame_id = child;
  m.transform = ToTransformMsg(T);
  return m;
}

geometry_msgs::PoseWithCovariance ToPoseWithCovarianceMsg(const pose_math::Pose& T, const pose_math::Matrix6d& cov6) {
  geometry_msgs::PoseWithCovariance m;
  m.pose = ToPoseMsg(T);
  Eigen::Map<RowMajor6d>(m.covariance.data()) = cov6;
  return m;
}

geometry_msgs::PoseWithCovariance ToPoseWithCovarianceMsg(const pose_math::PoseWithCovariance& T) {
  return ToPoseWithCovarianceMsg(T.pose, pose_math::CovarianceRosFromThesis(T.pose.q, T.cov));
}

void FromPoseWithCovarianceMsg(const geometry_msgs::PoseWithCovariance& m, pose_math::Pose* T,
                               pose_math::Matrix6d* cov6) {
  *T = FromPoseMsg(m.pose);
  *cov6 = Eigen::Map<const RowMajor6d>(m.covariance.data());
}

geometry_msgs::PoseWithCovarianceStamped ToPoseWithCovarianceStamped(const pose_math::PoseWithCovariance& T,
                                                                     const ros::Time& stamp, const std::string& frame) {
  geometry_msgs::PoseWithCovarianceStamped m;
  m.header.stamp = stamp;
  m.header.frame_id = frame;
  m.pose = ToPoseWithCovarianceMsg(T);
  return m;
}

geometry_msgs::TransformStamped ToTransformStamped(const CameraImuExtrinsics& e, const ros::Time& stamp) {
  pose_math::Pose T;
  T.q = pose_math::ThesisFromEigen(e.q_camera_imu);
  T.t = e.p_imu_in_camera_m;
  return ToTransformStamped(T, stamp, e.parent_frame, e.child_frame);
}

bool FromTransformStamped(const geometry_msgs::TransformStamped& m, CameraImuExtrinsics* e, std::string* why) {
  const pose_math::Pose T = FromTransformMsg(m.transform);
  if (!T.q.allFinite() || !T.t.allFinite()) {
    if (why) *why = "transform " + m.header.frame_id + " -> " + m.child_frame_id + " is not finite";
    return false;
  }
  if (T.q.norm() < 1e-6) {
    if (why) *why = "transform " + m.header.frame_id + " -> " + m.child_frame_id + " has a zero quaternion";
    return false;
  }
  e->parent_frame = m.header.frame_id;
  e->child_frame = m.child_frame_id;
  e->q_camera_imu = pose_math::EigenFromThesis(T.q.normalized());
  e->p_imu_in_camera_m = T.t;
  return true;
}

sensor_msgs::CameraInfo ToCameraInfo(const CameraModel& c, const ros::Time& stamp, const std::string& frame) {
  sensor_msgs::CameraInfo info;
  info.header.stamp = stamp;
  info.header.frame_id = frame;
  info.width = static_cast<uint32_t>(c.width_px);
  info.height = static_cast<uint32_t>(c.height_px);
  info.distortion_model = DistortionModelName(c.distortion_model);
  info.D = c.distortion;
  info.K = {c.fx_px, 0.0, c.cx_px, 0.0, c.fy_px, c.cy_px, 0.0, 0.0, 1.0};
  info.R = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  info.P = {c.fx_px, 0.0, c.cx_px, 0.0, 0.0, c.fy_px, c.cy_px, 0.0, 0.0, 0.0, 1.0, 0.0};
  return info;
}

bool FromCameraInfo(const sensor_msgs::CameraInfo& info, CameraModel* camera, std::string* why) {
  std::ostringstream err;
  const auto& K = info.K;
  bool finite = true;
  for (double k : K) finite = finite && std::isfinite(k);
  for (double d : info.D) finite = finite && std::isfinite(d);
  CameraModel c;
  if (!finite) {
    err << "camera_info has NaN or inf in K or D";
  } else if (!(K[0] > 0.0 && K[4] > 0.0)) {
    err << "camera_info K has focal lengths fx = " << K[0] << ", fy = " << K[4] << " (must be > 0; uncalibrated?)";
  } else if (!info.distortion_model.empty() && !DistortionModelFromName(info.distortion_model, &c.distortion_model)) {
    err << "camera_info distortion_model '" << info.distortion_model
        << "' is not supported (plumb_bob or rational_polynomial)";
  } else {
    if (info.distortion_model.empty() && info.D.size() == 8) c.distortion_model = DistortionModel::kRationalPolynomial;
    c.width_px = static_cast<int>(info.width), c.height_px = static_cast<int>(info.height);
    c.fx_px = K[0], c.fy_px = K[4], c.cx_px = K[2], c.cy_px = K[5];
    c.distortion.assign(info.D.begin(), info.D.end());
    const std::string problem = Validate(c);
    if (!problem.empty()) err << "camera_info: " << problem;
  }
  if (!err.str().empty()) {
    if (why) *why = err.str();
    return false;
  }
  *camera = c;
  return true;
}

sensor_msgs::RegionOfInterest ToRoi(const ImageBox& box, uint32_t width_px, uint32_t height_px, bool rectified) {
  sensor_msgs::RegionOfInterest roi;
  roi.do_rectify = rectified;
  if (!(std::isfinite(box.u_min) && std::isfinite(box.v_min) && std::isfinite(box.u_max) && std::isfinite(box.v_max)))
    return roi;
  const double u0 = std::max(0.0, std::floor(box.u_min + 0.5)), v0 = std::max(0.0, std::floor(box.v_min + 0.5));
  const double u1 = std::min(double(width_px) - 1.0, std::ceil(box.u_max - 0.5));
  const double v1 = std::min(double(height_px) - 1.0, std::ceil(box.v_max - 0.5));
  if (!(u1 >= u0 && v1 >= v0)) return roi;  // outside the image
  roi.x_offset = uint32_t(u0), roi.y_offset = uint32_t(v0);
  roi.width = uint32_t(u1 - u0) + 1, roi.height = uint32_t(v1 - v0) + 1;
  return roi;
}

ImageBox FromRoi(const sensor_msgs::RegionOfInterest& roi) {
  ImageBox b;
  b.u_min = double(roi.x_offset) - 0.5, b.v_min = double(roi.y_offset) - 0.5;
  b.u_max = double(roi.x_offset) + double(roi.width) - 0.5, b.v_max = double(roi.y_offset) + double(roi.height) - 0.5;
  return b;
}

}  // namespace rig_model
