#include "cone_tracker/pose/ransac.h"

#include <cmath>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "cone_tracker/pose/algorithms.h"

namespace cone_tracker {
namespace {

RansacPnpResult Failed(const std::string& why) {
  RansacPnpResult r;
  r.pnp.error = why;
  return r;
}

// Raw-pixel reprojection error of every point at T (CameraModel::Project: the lens model included); a point behind
// the camera gets infinity.
std::vector<double> Errors(const CameraModel& camera, const std::vector<Eigen::Vector3d>& model,
                           const std::vector<Eigen::Vector2d>& image, const pose_math::Pose& T) {
  const Eigen::Matrix3d R = RotationOf(T);
  std::vector<double> e(model.size(), INFINITY);
  Eigen::Vector2d uv;
  for (size_t i = 0; i < model.size(); ++i)
    if (camera.Project(R * model[i] + T.t, &uv)) e[i] = (uv - image[i]).norm();
  return e;
}

}  // namespace

RansacPnpResult SolvePnpRansac(const CameraModel& camera, const std::vector<Eigen::Vector3d>& model_points,
                               const std::vector<Eigen::Vector2d>& image_points_px, const PnpOptions& options,
                               const RansacOptions& ransac) {
  const size_t n = model_points.size();
  if (image_points_px.size() != n) return Failed("model and image have different numbers of points");
  if (n < 4) return Failed("RANSAC needs at least 4 points, got " + std::to_string(n));
  if (!(ransac.threshold_px > 0.0) || !(ransac.confidence > 0.0 && ransac.confidence < 1.0) ||
      ransac.max_iterations < 1)
    return Failed("RANSAC needs threshold_px > 0, 0 < confidence < 1 and max_iterations >= 1");
  std::vector<cv::Point3d> model(n);
  std::vector<cv::Point2d> image(n);
  for (size_t i = 0; i < n; ++i) {
    if (!model_points[i].allFinite() || !image_points_px[i].allFinite())
      return Failed("point " + std::to_string(i) + " is not finite (NaN or inf)");
    model[i] = {model_points[i].x(), model_points[i].y(), model_points[i].z()};
    image[i] = {image_points_px[i].x(), image_points_px[i].y()};
  }
  cv::Mat rvec, tvec;
  std::vector<int> consensus;
  bool found = false;
  try {
    const cv::Matx33d K(camera.fx_px, 0, camera.cx_px, 0, camera.fy_px, camera.cy_px, 0, 0, 1);
    found = cv::solvePnPRansac(model, image, K, camera.distortion, rvec, tvec, false, ransac.max_iterations,
                               float(ransac.threshold_px), ransac.confidence, consensus, cv::SOLVEPNP_P3P);
  } catch (const cv::Exception& e) {
    return Failed(std::string("RANSAC: ") + e.what());
  }
  if (!found || consensus.size() < 4) return Failed("RANSAC found no consensus of 4 or more points");
  cv::Mat R_cv;
  cv::Rodrigues(rvec, R_cv);
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  cv::cv2eigen(R_cv, R);
  cv::cv2eigen(tvec, t);
  pose_math::Pose start = PoseFromRt(R, t);

  RansacPnpResult r;
  std::vector<char> inlier(n, 0);
  for (int i : consensus) inlier[size_t(i)] = 1;
  for (int round = 0; round < 2; ++round) {
    std::vector<Eigen::Vector3d> m;
    std::vector<Eigen::Vector2d> p;
    for (size_t i = 0; i < n; ++i)
      if (inlier[i]) m.push_back(model_points[i]), p.push_back(image_points_px[i]);
    r.pnp = SolvePnp(camera, m, p, options, start);
    if (!r.pnp.ok) {
      r.pnp.error = "on the " + std::to_string(m.size()) + " RANSAC inliers: " + r.pnp.error;
      return r;
    }
    r.inlier = inlier, r.num_inliers = int(m.size());
    const std::vector<double> e = Errors(camera, model_points, image_points_px, r.pnp.T_camera_model);
    std::vector<char> again(n, 0);
    for (size_t i = 0; i < n; ++i) again[i] = e[i] < ransac.threshold_px;
    if (again == inlier) break;
    inlier = again, start = r.pnp.T_camera_model;
  }
  return r;
}

}  // namespace cone_tracker
