#include "rig_sim/ros/messages.h"

#include <cmath>

#include <Eigen/Geometry>

#include "rig_model/ros/conversions.h"

namespace rig_sim {
namespace {

pose_math::Pose PoseOf(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  pose_math::Pose T;
  T.q = pose_math::ThesisFromEigen(Eigen::Quaterniond(R));
  T.t = t;
  return T;
}

// An Imu message with no orientation estimate (REP-145) and no covariances yet.
sensor_msgs::Imu ImuMessage(const Eigen::Vector3d& omega, const Eigen::Vector3d& accel, const ros::Time& stamp,
                            const std::string& frame) {
  sensor_msgs::Imu m;
  m.header.stamp = stamp;
  m.header.frame_id = frame;
  m.orientation_covariance[0] = -1.0;
  m.angular_velocity.x = omega.x();
  m.angular_velocity.y = omega.y();
  m.angular_velocity.z = omega.z();
  m.linear_acceleration.x = accel.x();
  m.linear_acceleration.y = accel.y();
  m.linear_acceleration.z = accel.z();
  return m;
}

}  // namespace

ros::Time StampAt(double start_s, double t_s) {
  const int64_t ns = static_cast<int64_t>(std::llround(start_s * 1e9)) + static_cast<int64_t>(std::llround(t_s * 1e9));
  ros::Time stamp;
  stamp.fromNSec(static_cast<uint64_t>(ns));
  return stamp;
}

sensor_msgs::CameraInfo MakeCameraInfo(const CameraConfig& c, const ros::Time& stamp, const std::string& frame) {
  return rig_model::ToCameraInfo(c.model, stamp, frame);
}

sensor_msgs::ImagePtr MakeEmptyImage(const CameraConfig& c, const ros::Time& stamp, const std::string& frame) {
  sensor_msgs::ImagePtr img(new sensor_msgs::Image);
  img->header.stamp = stamp;
  img->header.frame_id = frame;
  img->width = c.model.width_px;
  img->height = c.model.height_px;
  img->encoding = "rgb8";
  img->is_bigendian = 0;
  img->step = 3 * c.model.width_px;
  img->data.resize(static_cast<size_t>(img->step) * img->height);
  return img;
}

ros::Time ImuMessageStamp(const ros::Time& interval_end, const ImuConfig& config) {
  return interval_end - ros::Duration(0.5 / config.rate_hz);
}

sensor_msgs::Imu MakeImu(const ImuSample& s, const ImuConfig& cfg, const ros::Time& stamp, const std::string& frame) {
  sensor_msgs::Imu m = ImuMessage(s.omega_imu_rad_s, s.accel_imu_m_s2, stamp, frame);
  const double g = cfg.gyro_noise_deg_s * M_PI / 180.0, a = cfg.accel_noise_m_s2;
  for (int i = 0; i < 3; ++i) {
    m.angular_velocity_covariance[4 * i] = g * g;
    m.linear_acceleration_covariance[4 * i] = a * a;
  }
  return m;
}

sensor_msgs::Imu MakeImuBias(const ImuSample& s, const ros::Time& stamp, const std::string& frame) {
  return ImuMessage(s.true_gyro_bias_rad_s, s.true_accel_bias_m_s2, stamp, frame);
}

geometry_msgs::PoseStamped MakeTruthPose(const TruePose& pose, const ros::Time& stamp, const std::string& frame) {
  geometry_msgs::PoseStamped m;
  m.header.stamp = stamp;
  m.header.frame_id = frame;
  m.pose = rig_model::ToPoseMsg(PoseOf(pose.R_cones_camera, pose.p_camera_in_cones_m));
  return m;
}

geometry_msgs::TransformStamped MakeTruthTransform(const TruePose& pose, const ros::Time& stamp,
                                                   const FrameNames& frames) {
  return rig_model::ToTransformStamped(PoseOf(pose.R_cones_camera, pose.p_camera_in_cones_m), stamp, frames.cones,
                                       frames.camera_truth);
}

tf2_msgs::TFMessage MakeStaticTruth(const ImuConfig& imu, const ros::Time& stamp, const FrameNames& frames) {
  tf2_msgs::TFMessage out;
  out.transforms.push_back(rig_model::ToTransformStamped(imu.Extrinsics(frames.camera_truth, frames.imu_truth), stamp));
  return out;
}

visualization_msgs::MarkerArray MakeConeMarkers(const Scene& scene, const ros::Time& stamp, const std::string& frame) {
  visualization_msgs::MarkerArray out;
  const int kSides = 24;
  for (size_t i = 0; i < scene.cones.size(); ++i) {
    const ConeSpec& c = scene.cones[i];
    visualization_msgs::Marker m;
    m.header.stamp = stamp;
    m.header.frame_id = frame;
    m.ns = "cones";
    m.id = static_cast<int>(i);
    m.type = visualization_msgs::Marker::TRIANGLE_LIST;
    m.action = visualization_msgs::Marker::ADD;
    m.pose.orientation.w = 1.0;
    m.scale.x = m.scale.y = m.scale.z = 1.0;
    m.color.r = 1.0f;
    m.color.g = 0.4f;
    m.color.b = 0.05f;
    m.color.a = 1.0f;
    geometry_msgs::Point apex;
    apex.x = c.peak_m().x();
    apex.y = c.peak_m().y();
    apex.z = c.peak_m().z();
    for (int k = 0; k < kSides; ++k) {
      for (int j : {k, k + 1}) {
        geometry_msgs::Point p;
        const double a = 2.0 * M_PI * j / kSides;
        p.x = c.base_m.x() + c.radius_m() * std::cos(a);
        p.y = c.base_m.y() + c.radius_m() * std::sin(a);
        p.z = c.base_m.z();
        m.points.push_back(p);
      }
      m.points.push_back(apex);
    }
    out.markers.push_back(m);
  }
  return out;
}

}  // namespace rig_sim
