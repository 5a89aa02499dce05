// Helpers of the association tests (test_associate.cpp, test_associate_recorded.cpp): the layout, the camera
// and the recorded priors of rig_sim's look_away frames. Test code only.
#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "cone_tracker/pose/associate.h"
#include "cone_tracker/vision/cone_pose.h"
#include "cone_tracker/vision/segmenter.h"
#include "pose_math/rotation.h"

namespace cone_tracker {
namespace association_test {

// rig_model's asymmetric.yaml: a short third cone and uneven spacing.
inline std::vector<ConeModel> Asymmetric() {
  std::vector<ConeModel> l(3);
  l[0].base_m = {1.00, 0.00, 0}, l[1].base_m = {-0.40, 0.85, 0}, l[2].base_m = {-0.60, -0.85, 0};
  l[2].height_m = 0.46;
  return l;
}

// The camera at `eye` (in `cones`) looking at `target`, y down: T_camera_cones.
inline pose_math::Pose PoseLookingAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R_cones_camera;
  R_cones_camera << x, y, z;
  pose_math::Pose T;
  T.q = pose_math::QuatFromRotation(R_cones_camera.transpose());
  T.t = -(R_cones_camera.transpose() * eye);
  return T;
}

// rig_sim's camera at 512x384 (undistorted pixels).
inline CameraModel RigSim512() {
  CameraModel cam;
  cam.width_px = 512, cam.height_px = 384, cam.fx_px = 385, cam.fy_px = 388, cam.cx_px = 255.5, cam.cy_px = 191.5;
  return cam;
}

// T_camera_cones of a camera at eye (in `cones`) turned by q_cones_camera, as rig_sim/ground_truth and pose_ekf/pose
// give it.
inline pose_math::Pose CameraAt(const Eigen::Vector3d& eye, const Eigen::Quaterniond& q_cones_camera) {
  pose_math::Pose T;
  const Eigen::Matrix3d R = q_cones_camera.toRotationMatrix().transpose();
  T.q = pose_math::QuatFromRotation(R), T.t = -(R * eye);
  return T;
}

// The association's prior as cone_tracker's node makes it from pose_ekf/pose (orientation q_pred, ROS covariance):
// the filter's covariance plus 2 degrees and 5 cm.
inline AssociationConfig RecordedPrior(const Eigen::Quaterniond& q_pred, const Eigen::Matrix<double, 6, 6>& cov_ros) {
  AssociationConfig cfg;
  cfg.prediction_cov = AssociationPrior(pose_math::Quat(q_pred.w(), q_pred.x(), q_pred.y(), q_pred.z()), cov_ros);
  cfg.prediction_cov->diagonal() +=
      (Eigen::Matrix<double, 6, 1>() << Eigen::Vector3d::Constant(std::pow(2.0 * M_PI / 180.0, 2)),
       Eigen::Vector3d::Constant(0.05 * 0.05))
          .finished();
  return cfg;
}

// The orange regions of a cone's silhouette as the segmenter reports them (SegmentationResult::orange_undist_px):
// boxes around four bands of its rows.
inline std::vector<rig_model::ImageBox> Slabs(const rig_model::ConeSilhouette& s) {
  std::vector<rig_model::ImageBox> out;
  for (int i = 0; i < kOrangeSlabs; ++i) {
    const double f0 = double(i) / kOrangeSlabs, f1 = double(i + 1) / kOrangeSlabs;
    const Eigen::Vector2d a = s.peak_px + f0 * (s.base_px - s.peak_px), b = s.peak_px + f1 * (s.base_px - s.peak_px);
    out.push_back(rig_model::SilhouetteBox(a, b, f1 * s.half_width_px));
  }
  return out;
}

}  // namespace association_test
}  // namespace cone_tracker
