#include "opencv_baseline.h"

#include <opencv2/calib3d.hpp>

#include "pose_math/rotation.h"

namespace cone_tracker {
namespace baseline {

const std::vector<OpenCvMethod>& OpenCvMethods() {
  static const std::vector<OpenCvMethod> methods{
      {cv::SOLVEPNP_ITERATIVE, "cv-iterative"}, {cv::SOLVEPNP_EPNP, "cv-epnp"}, {cv::SOLVEPNP_SQPNP, "cv-sqpnp"}};
  return methods;
}

bool SolveOpenCv(int flag, const CameraModel& camera, const std::vector<Eigen::Vector3d>& model,
                 const std::vector<Eigen::Vector2d>& image, pose_math::Pose* T_camera_model) {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> pixels;
  for (const Eigen::Vector3d& m : model) object.emplace_back(m.x(), m.y(), m.z());
  for (const Eigen::Vector2d& p : image) pixels.emplace_back(p.x(), p.y());
  const cv::Matx33d K(camera.fx_px, 0, camera.cx_px, 0, camera.fy_px, camera.cy_px, 0, 0, 1);
  cv::Mat rvec, tvec;
  try {
    if (!cv::solvePnP(object, pixels, K, camera.distortion, rvec, tvec, false, flag)) return false;
  } catch (const cv::Exception&) {
    return false;
  }
  const Eigen::Vector3d r(rvec.at<double>(0), rvec.at<double>(1), rvec.at<double>(2));
  T_camera_model->q = pose_math::QuatFromRotationVector(r);
  T_camera_model->t = Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  return T_camera_model->q.allFinite() && T_camera_model->t.allFinite();
}

}  // namespace baseline
}  // namespace cone_tracker
