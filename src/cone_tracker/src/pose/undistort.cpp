// Pixel observations to undistorted, normalised image points (4.4), with
// OpenCV's iterative inverse of its distortion model. Kept in its own file so
// only this translation unit includes OpenCV.
#include <opencv2/calib3d.hpp>

#include "undistort.h"

namespace cone_tracker {

bool NormalizeImagePoints(const CameraModel& camera, const std::vector<Eigen::Vector2d>& image_points_px,
                          Eigen::Matrix2Xd* normalized) {
  const int n = static_cast<int>(image_points_px.size());
  normalized->resize(2, n);
  if (!camera.HasDistortion()) {
    for (int i = 0; i < n; ++i) {
      (*normalized)(0, i) = (image_points_px[i].x() - camera.cx_px) / camera.fx_px;
      (*normalized)(1, i) = (image_points_px[i].y() - camera.cy_px) / camera.fy_px;
    }
    return true;
  }
  std::vector<cv::Point2d> src(n), dst;
  for (int i = 0; i < n; ++i) src[i] = cv::Point2d(image_points_px[i].x(), image_points_px[i].y());
  const cv::Matx33d K(camera.fx_px, 0, camera.cx_px, 0, camera.fy_px, camera.cy_px, 0, 0, 1);
  cv::undistortPoints(src, dst, K, camera.distortion);
  for (int i = 0; i < n; ++i) {
    (*normalized)(0, i) = dst[i].x;
    (*normalized)(1, i) = dst[i].y;
  }
  return normalized->allFinite();
}

}  // namespace cone_tracker
