// Messages <-> the rig's core types, written once: poses (pose_math, thesis quaternion order
// [q0 qx qy qz]) to and from geometry_msgs Pose / Transform / PoseWithCovariance(Stamped), the
// camera-IMU extrinsics to and from a TransformStamped, rig_model::CameraModel to and from
// sensor_msgs/CameraInfo, and image boxes to and from sensor_msgs/RegionOfInterest. Covariances in messages are ROS's
// 6x6 (x y z rx ry rz), row-major; pose_math owns the map to and from the thesis's constrained 7x7 (5.6.4).
#pragma once

#include <string>

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/PoseWithCovariance.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/Transform.h>
#include <geometry_msgs/TransformStamped.h>
#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/RegionOfInterest.h>

#include "pose_math/pose.h"
#include "rig_model/camera_imu.h"
#include "rig_model/camera_model.h"
#include "rig_model/cone_view.h"

namespace rig_model {

// Poses. The From* functions copy the quaternion as it is (not normalised): callers check it.
geometry_msgs::Pose ToPoseMsg(const pose_math::Pose& T);
pose_math::Pose FromPoseMsg(const geometry_msgs::Pose& msg);
geometry_msgs::Transform ToTransformMsg(const pose_math::Pose& T);
pose_math::Pose FromTransformMsg(const geometry_msgs::Transform& msg);
// T_parent_child as tf: header.frame_id = parent, child_frame_id = child.
geometry_msgs::TransformStamped ToTransformStamped(const pose_math::Pose& T_parent_child, const ros::Time& stamp,
                                                   const std::string& parent, const std::string& child);

// Poses with covariance, the 6x6 in ROS's form.
geometry_msgs::PoseWithCovariance ToPoseWithCovarianceMsg(const pose_math::Pose& T, const pose_math::Matrix6d& cov6);
// The thesis's 7x7 over (q, t) mapped to ROS's 6x6 at T.pose.q (pose_math::CovarianceRosFromThesis).
geometry_msgs::PoseWithCovariance ToPoseWithCovarianceMsg(const pose_math::PoseWithCovariance& T);
void FromPoseWithCovarianceMsg(const geometry_msgs::PoseWithCovariance& msg, pose_math::Pose* T,
                               pose_math::Matrix6d* cov6);
geometry_msgs::PoseWithCovarianceStamped ToPoseWithCovarianceStamped(const pose_math::PoseWithCovariance& T,
                                                                     const ros::Time& stamp, const std::string& frame);

// The extrinsics as the static tf parent_frame -> child_frame (camera_optical -> imu).
geometry_msgs::TransformStamped ToTransformStamped(const CameraImuExtrinsics& extrinsics, const ros::Time& stamp);
// The rotation is normalised; false with *why when it is not finite or has zero norm.
bool FromTransformStamped(const geometry_msgs::TransformStamped& msg, CameraImuExtrinsics* extrinsics,
                          std::string* why);

// camera_info with K, R = I and P = [K | 0] of an unrectified camera, D and distortion_model from `camera`.
sensor_msgs::CameraInfo ToCameraInfo(const CameraModel& camera, const ros::Time& stamp, const std::string& frame);
// False with a reason naming what is wrong (NaN/inf, zero focal length, an unsupported
// distortion_model, a coefficient count the model does not have); *camera untouched then.
// An empty distortion_model takes eight coefficients as rational_polynomial, others as plumb_bob.
bool FromCameraInfo(const sensor_msgs::CameraInfo& info, CameraModel* camera, std::string* why);

// An image box (pixel centres at integers: pixel x spans x - 0.5 .. x + 0.5) as the whole pixels it touches,
// clipped to a width x height image; do_rectify marks a box in undistorted pixels. A box wholly outside the
// image gives width 0. FromRoi gives back the pixels' outer edges, so the round trip only grows a box.
sensor_msgs::RegionOfInterest ToRoi(const ImageBox& box, uint32_t width_px, uint32_t height_px, bool rectified);
ImageBox FromRoi(const sensor_msgs::RegionOfInterest& roi);

}  // namespace rig_model
