// Renders a scene YAML over a picture (or a synthetic floor with the cones
// frame's grid drawn by cv::projectPoints, so placement can be checked by eye)
// and writes the composited PNG.
// Usage: ar_overlay_render <scene.yaml> <out.png> [eye_x eye_y eye_z] [background.png]
#include <Eigen/Core>
#include <cstdio>
#include <cstdlib>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ar_overlay/core/overlay.h"

using namespace ar_overlay;

namespace {

// A grey floor with a 0.1 m grid and the cones frame's x (red) and y (green) axes.
cv::Mat Floor(const CameraModel& k, const Eigen::Isometry3d& T_camera_cones) {
  cv::Mat img(k.height_px, k.width_px, CV_8UC3, cv::Scalar(90, 95, 100));
  cv::Mat R, rvec;
  cv::eigen2cv(Eigen::Matrix3d(T_camera_cones.linear()), R);
  cv::Rodrigues(R, rvec);
  const Eigen::Vector3d t = T_camera_cones.translation();
  const cv::Matx33d K(k.fx_px, 0, k.cx_px, 0, k.fy_px, k.cy_px, 0, 0, 1);
  auto line = [&](cv::Point3d a, cv::Point3d b, cv::Scalar color, int width) {
    std::vector<cv::Point3d> pts;
    for (int i = 0; i <= 40; ++i) pts.push_back(a + (b - a) * (i / 40.0));  // curved by the distortion
    std::vector<cv::Point2d> px;
    cv::projectPoints(pts, rvec, cv::Vec3d(t.x(), t.y(), t.z()), K, k.distortion, px);
    for (size_t i = 1; i < px.size(); ++i) cv::line(img, px[i - 1], px[i], color, width, cv::LINE_AA);
  };
  for (int i = -10; i <= 10; ++i) {
    line({i * 0.1, -1, 0}, {i * 0.1, 1, 0}, cv::Scalar(150, 150, 150), 1);
    line({-1, i * 0.1, 0}, {1, i * 0.1, 0}, cv::Scalar(150, 150, 150), 1);
  }
  line({0, 0, 0}, {0.3, 0, 0}, cv::Scalar(0, 0, 255), 3);
  line({0, 0, 0}, {0, 0.3, 0}, cv::Scalar(0, 200, 0), 3);
  return img;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && argc != 6 && argc != 7) {
    std::fprintf(stderr, "usage: %s <scene.yaml> <out.png> [eye_x eye_y eye_z] [background.png]\n", argv[0]);
    return 2;
  }
  Eigen::Vector3d eye(1.0, -1.3, 0.9);
  for (int i = 0; argc >= 6 && i < 3; ++i) {
    char* end = nullptr;
    eye[i] = std::strtod(argv[3 + i], &end);
    if (end == argv[3 + i] || *end != '\0') {
      std::fprintf(stderr, "ar_overlay_render: eye_%c must be a number in metres, got '%s'\n", "xyz"[i], argv[3 + i]);
      return 2;
    }
  }
  const CameraModel k{1024, 768, 800, 800, 511.5, 383.5, {-0.2, 0.05, 0, 0, 0}};
  const Eigen::Isometry3d T_camera_cones = CameraLookAt(eye, Eigen::Vector3d(0, 0, 0.3)).inverse();
  try {
    Overlay overlay;
    const std::vector<std::string> load_errors = overlay.LoadScene(argv[1]);
    for (const std::string& e : load_errors)
      std::fprintf(stderr, "ar_overlay_render: %s: model not loaded: %s\n", argv[1], e.c_str());
    overlay.SetJointPositions({{"joint_a1", 0.5}, {"joint_a2", -0.4}, {"joint_a3", 0.6}, {"joint_a5", 0.8}});
    cv::Mat background = Floor(k, T_camera_cones);
    if (argc == 7 || argc == 4) {
      background = cv::imread(argv[argc - 1]);
      if (background.empty()) {
        std::fprintf(stderr, "ar_overlay_render: cannot read the background image %s\n", argv[argc - 1]);
        return 1;
      }
      cv::resize(background, background, cv::Size(k.width_px, k.height_px));
    }
    std::string enc;
    cv::Mat out;
    overlay.Process(background, "bgr8", k, T_camera_cones, out, enc);
    if (!cv::imwrite(argv[2], out)) {
      std::fprintf(stderr, "ar_overlay_render: cannot write %s\n", argv[2]);
      return 1;
    }
    std::printf("wrote %s (%s)\n", argv[2], overlay.gl_renderer().c_str());
    if (!load_errors.empty()) return 1;  // written, but without the models named above
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ar_overlay_render: %s\n", e.what());
    return 1;
  }
  return 0;
}
