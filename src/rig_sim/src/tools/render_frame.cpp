// Renders one frame of the default scene to a PNG, to look at: render_frame OUT.png [t_s] [layout.yaml]
#include <cstdio>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "rig_sim/renderer.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: render_frame OUT.png [t_s] [layout.yaml]\n");
    return 2;
  }
  const double t = argc > 2 ? std::stod(argv[2]) : 0.0;
  rig_sim::Scene scene = rig_sim::DefaultScene();
  std::string err;
  if (argc > 3 && !rig_sim::LoadSceneYaml(argv[3], &scene, &err)) {
    std::fprintf(stderr, "%s\n", err.c_str());
    return 1;
  }
  rig_sim::TrajectoryConfig tc;
  const rig_sim::Trajectory traj(tc);
  const rig_sim::CameraModel camera{rig_sim::CameraConfig()};
  const rig_sim::Renderer renderer(camera, scene, rig_sim::RenderConfig());
  cv::Mat rgb(renderer.height(), renderer.width(), CV_8UC3);
  renderer.Render(traj.At(t), t, 0, rgb.data);
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  return cv::imwrite(argv[1], bgr) ? 0 : 1;
}
