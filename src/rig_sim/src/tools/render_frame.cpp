// Renders one frame of a scenario to a PNG, to look at:
//   render_frame OUT.png [t_s] [scenario] [seed] [scale]
#include <cstdio>
#include <exception>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "rig_sim/sim_stream.h"

namespace {
constexpr const char* kUsage =
    "usage: render_frame OUT.png [t_s] [scenario] [seed] [scale] [look]\n"
    "Renders the frame the simulated camera sees at t_s (default 0) of the scenario (default handheld),\n"
    "in the given look (default: the scenario's; make_bag --help lists the looks).\n";

int Run(int argc, char** argv) {
  const std::string out = argv[1];
  if (out.size() < 5 || out.substr(out.size() - 4) != ".png") {
    std::fprintf(stderr, "render_frame: the output must be a .png file, got '%s'\n%s", out.c_str(), kUsage);
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
  if (argc > 6 && !rig_sim::ApplyLook(argv[6], &scenario, &err)) {
    std::fprintf(stderr, "render_frame: %s\n", err.c_str());
    return 1;
  }
  rig_sim::ShortenScenario(0.0, argc > 5 ? std::stod(argv[5]) : 1.0, &scenario);
  const rig_sim::SimStream stream(scenario, rig_sim::StreamConfig());
  cv::Mat rgb(scenario.camera.model.height_px, scenario.camera.model.width_px, CV_8UC3);
  stream.RenderFrame(stream.ImageEventAt(t), rgb.data);
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  if (!cv::imwrite(out, bgr)) {
    std::fprintf(stderr, "render_frame: could not write %s\n", out.c_str());
    return 1;
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    std::fprintf(argc < 2 ? stderr : stdout, "%s", kUsage);
    return argc < 2 ? 2 : 0;
  }
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {  // a number that does not parse, a file that cannot be written
    std::fprintf(stderr, "render_frame: %s\n%s", e.what(), kUsage);
    return 2;
  }
}
