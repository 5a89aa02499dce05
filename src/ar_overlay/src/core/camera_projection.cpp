#include "ar_overlay/core/camera_projection.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

namespace ar_overlay {

Eigen::Matrix4f ProjectionFromIntrinsics(double fx, double fy, double cx, double cy, int width, int height,
                                         double near_m, double far_m) {
  // The pinhole projection u = fu X/Z + u0 (3.6) with K of (3.8), in clip coordinates.
  // NDC x = 2 (u + 0.5) / W - 1 puts pixel centre u at the centre of column u;
  // with y likewise (not flipped), NDC y = -1 is framebuffer row 0 = image top.
  Eigen::Matrix4f P = Eigen::Matrix4f::Zero();
  P(0, 0) = static_cast<float>(2.0 * fx / width);
  P(0, 2) = static_cast<float>(2.0 * (cx + 0.5) / width - 1.0);
  P(1, 1) = static_cast<float>(2.0 * fy / height);
  P(1, 2) = static_cast<float>(2.0 * (cy + 0.5) / height - 1.0);
  P(2, 2) = static_cast<float>((far_m + near_m) / (far_m - near_m));
  P(2, 3) = static_cast<float>(-2.0 * far_m * near_m / (far_m - near_m));
  P(3, 2) = 1.0f;  // w_clip = z_camera
  return P;
}

Eigen::Isometry3d CameraLookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();  // optical axis
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());  // image right
  if (x.norm() < 1e-9) x = Eigen::Vector3d::UnitX();      // looking straight up or down
  x.normalize();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << x, z.cross(x), z;  // columns: the camera's axes in cones; y = z x x points down
  T.translation() = eye;
  return T;
}

DistortionMap::DistortionMap(const CameraModel& k) {
  const int W = k.width_px, H = k.height_px;
  canvas_width_ = W;
  canvas_height_ = H;
  canvas_cx_ = k.cx_px;
  canvas_cy_ = k.cy_px;
  identity_ = !k.HasDistortion();
  K_ = cv::Matx33d(k.fx_px, 0, k.cx_px, 0, k.fy_px, k.cy_px, 0, 0, 1);
  distortion_ = k.distortion;
  if (identity_) return;

  const cv::Matx33d K(k.fx_px, 0, k.cx_px, 0, k.fy_px, k.cy_px, 0, 0, 1);
  const cv::Mat D(k.distortion, true);
  // Every raw pixel's position in the ideal pinhole image (P = K).
  std::vector<cv::Point2f> raw;
  raw.reserve(static_cast<size_t>(W) * H);
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u) raw.emplace_back(static_cast<float>(u), static_cast<float>(v));
  std::vector<cv::Point2f> ideal;
  cv::undistortPoints(raw, ideal, K, D, cv::noArray(), K,
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-6));

  // The canvas covers where the raw image looks, within twice the image size.
  float x0 = 0, y0 = 0, x1 = static_cast<float>(W - 1), y1 = static_cast<float>(H - 1);
  for (const auto& p : ideal) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
    x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  }
  x0 = std::max(x0, -0.5f * W), y0 = std::max(y0, -0.5f * H);
  x1 = std::min(x1, 1.5f * W), y1 = std::min(y1, 1.5f * H);
  const int margin_left = static_cast<int>(std::ceil(-x0)) + 2, margin_top = static_cast<int>(std::ceil(-y0)) + 2;
  canvas_width_ = margin_left + static_cast<int>(std::ceil(x1)) + 3;
  canvas_height_ = margin_top + static_cast<int>(std::ceil(y1)) + 3;
  canvas_cx_ = k.cx_px + margin_left;
  canvas_cy_ = k.cy_px + margin_top;

  cv::Mat map(H, W, CV_32FC2);
  for (int v = 0; v < H; ++v) {
    auto* row = map.ptr<cv::Vec2f>(v);
    for (int u = 0; u < W; ++u) {
      const cv::Point2f& p = ideal[static_cast<size_t>(v) * W + u];
      row[u] = cv::Vec2f(p.x + margin_left, p.y + margin_top);
    }
  }
  cv::convertMaps(map, cv::noArray(), map1_, map2_, CV_16SC2);  // fixed point: remap is about twice as fast
}

cv::Rect DistortionMap::RawRoi(const cv::Rect& canvas_roi) const {
  const cv::Rect image(0, 0, identity_ ? canvas_width_ : static_cast<int>(map1_.cols),
                       identity_ ? canvas_height_ : static_cast<int>(map1_.rows));
  if (identity_ || canvas_roi.empty()) return canvas_roi & image;
  // The map is continuous and one-to-one, so the image of the box's boundary
  // bounds the image of the box: distort samples along the boundary.
  const double ox = canvas_cx_ - K_(0, 2), oy = canvas_cy_ - K_(1, 2);
  std::vector<cv::Point3d> rays;
  const int n = 24;
  for (int i = 0; i <= n; ++i) {
    const double a = canvas_roi.x + canvas_roi.width * static_cast<double>(i) / n;
    const double b = canvas_roi.y + canvas_roi.height * static_cast<double>(i) / n;
    for (const cv::Point2d& c : {cv::Point2d(a, canvas_roi.y), cv::Point2d(a, canvas_roi.br().y),
                                 cv::Point2d(canvas_roi.x, b), cv::Point2d(canvas_roi.br().x, b)})
      rays.emplace_back((c.x - ox - K_(0, 2)) / K_(0, 0), (c.y - oy - K_(1, 2)) / K_(1, 1), 1.0);
  }
  std::vector<cv::Point2d> raw;
  cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K_, distortion_, raw);
  double x0 = raw[0].x, x1 = x0, y0 = raw[0].y, y1 = y0;
  for (const auto& p : raw)
    x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  const double big = 4.0 * (image.width + image.height);  // keeps the int conversion sane
  x0 = std::max(x0, -big), y0 = std::max(y0, -big), x1 = std::min(x1, big), y1 = std::min(y1, big);
  const cv::Rect r(static_cast<int>(std::floor(x0)) - 2, static_cast<int>(std::floor(y0)) - 2,
                   static_cast<int>(std::ceil(x1 - x0)) + 5, static_cast<int>(std::ceil(y1 - y0)) + 5);
  return r & image;
}

void DistortionMap::ApplyRoi(const cv::Mat& canvas, const cv::Rect& raw_roi, cv::Mat& raw) const {
  if (identity_) {
    canvas(raw_roi).copyTo(raw(raw_roi));
    return;
  }
  cv::Mat out = raw(raw_roi);
  cv::remap(canvas, out, map1_(raw_roi), map2_(raw_roi), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(0));
}

void DistortionMap::Apply(const cv::Mat& canvas, cv::Mat& raw) const {
  if (identity_) {
    raw = canvas;
    return;
  }
  cv::remap(canvas, raw, map1_, map2_, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(0));
}

}  // namespace ar_overlay
