// Renders one frame of a scenario to a PNG, to look at:
//   render_frame OUT.png [t_s] [scenario] [seed] [scale]
#include <cstdio>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "rig_sim/sim_stream.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: render_frame OUT.png [t_s] [scenario] [seed] [scale]\n");
    return 2;
  }
  const double t = argc > 2 ? std::stod(argv[2]) : 0.0;
  const std::string name = argc > 3 ? argv[3] : "handheld";
  const uint64_t seed = argc > 4 ? std::stoull(argv[4]) : 1;
  rig_sim::Scenario scenario;
  std::string err;
  if (!rig_sim::MakeScenario(name, seed, RIG_SIM_LAYOUTS_DIR, &scenario, &err)) {
    std::fprintf(stderr, "render_frame: %s\n", err.c_str());
    return 1;
  }
  rig_sim::ShortenScenario(0.0, argc > 5 ? std::stod(argv[5]) : 1.0, &scenario);
  const rig_sim::SimStream stream(scenario, rig_sim::StreamConfig());
  rig_sim::SimEvent ev;
  ev.kind = rig_sim::EventKind::kImage;
  ev.stamp_s = t;
  ev.pose = stream.trajectory().At(t);
  cv::Mat rgb(scenario.camera.height_px, scenario.camera.width_px, CV_8UC3);
  stream.RenderFrame(ev, rgb.data);
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  return cv::imwrite(argv[1], bgr) ? 0 : 1;
}
