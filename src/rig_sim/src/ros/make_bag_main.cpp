// rosrun rig_sim make_bag --scenario NAME --seed N --output FILE.bag [options]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "rig_sim/outage_plan.h"
#include "rig_sim/ros/bag_writer.h"

namespace {

void Usage() {
  std::printf(
      "usage: make_bag [--scenario NAME] [--seed N] --output FILE.bag [options]\n"
      "Writes a simulated rig's camera, IMU and ground truth straight into a rosbag.\n\n"
      "options:\n"
      "  --scenario NAME        default handheld\n"
      "  --seed N               default 1; the same seed gives an identical bag\n"
      "  --duration S           cut the scenario to S seconds\n"
      "  --scale F              image scale, e.g. 0.25 for 256x192 (intrinsics scale with it)\n"
      "  --camera-delay-ms MS   deliver each frame MS after its exposure stamp (default 0)\n"
      "  --compression C        none (default), lz4 or bz2\n"
      "  --noise-sigma DN       image noise (default 2, or the look's; 0 for none)\n"
      "  --look NAME            how the world and the camera look (default: the scenario's, plain\n"
      "                         for all but realistic); see looks below\n"
      "  --layouts DIR          directory of layout files (default: rig_model's config/layouts)\n"
      "  --layout FILE          use this layout file instead of the scenario's (the survey walk\n"
      "                         circles any layout, site_look_away plans its outages on it;\n"
      "                         random ones: rosrun rig_sim make_layout)\n\n"
      "scenarios:\n");
  for (const auto& s : rig_sim::ListScenarios()) std::printf("  %-10s %s\n", s.name.c_str(), s.description.c_str());
  std::printf("\nlooks:\n");
  for (const auto& s : rig_sim::ListLooks()) std::printf("  %-10s %s\n", s.name.c_str(), s.description.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  std::string scenario_name = "handheld", output, layouts = RIG_SIM_LAYOUTS_DIR, layout_file, compression = "none",
              look;
  uint64_t seed = 1;
  double duration = 0.0, scale = 1.0, delay_ms = 0.0, noise = -1.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "make_bag: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    try {
      if (a == "--help" || a == "-h") {
        Usage();
        return 0;
      } else if (a == "--scenario")
        scenario_name = value();
      else if (a == "--seed")
        seed = std::stoull(value());
      else if (a == "--output" || a == "-o")
        output = value();
      else if (a == "--duration")
        duration = std::stod(value());
      else if (a == "--scale")
        scale = std::stod(value());
      else if (a == "--camera-delay-ms")
        delay_ms = std::stod(value());
      else if (a == "--compression")
        compression = value();
      else if (a == "--noise-sigma")
        noise = std::stod(value());
      else if (a == "--look")
        look = value();
      else if (a == "--layouts")
        layouts = value();
      else if (a == "--layout")
        layout_file = value();
      else {
        std::fprintf(stderr, "make_bag: unknown argument '%s' (see --help)\n", a.c_str());
        return 2;
      }
    } catch (const std::exception&) {
      std::fprintf(stderr, "make_bag: bad value for %s\n", a.c_str());
      return 2;
    }
  }
  if (output.empty()) {
    std::fprintf(stderr, "make_bag: --output FILE.bag is required (see --help)\n");
    return 2;
  }
  if (!(scale > 0.0 && scale <= 4.0) || duration < 0.0 || delay_ms < 0.0 || delay_ms > 1000.0) {
    std::fprintf(stderr, "make_bag: need 0 < --scale <= 4, --duration >= 0, 0 <= --camera-delay-ms <= 1000\n");
    return 2;
  }
  rig_sim::Scenario scenario;
  std::string err;
  if (!rig_sim::MakeScenario(scenario_name, seed, layouts, &scenario, &err) ||
      (!layout_file.empty() && !rig_sim::LoadSceneYaml(layout_file, &scenario.scene, &err)) ||
      (!look.empty() && !rig_sim::ApplyLook(look, &scenario, &err))) {
    std::fprintf(stderr, "make_bag: %s\n", err.c_str());
    return 1;
  }
  if (!rig_sim::FitTrajectoryToScene(&scenario, &err)) {
    std::fprintf(stderr, "make_bag: %s\n", err.c_str());
    return 1;
  }
  if (scenario.name == "site_look_away") {  // say when the outages are and which two cones end them
    rig_sim::Scenario copy = scenario;
    std::vector<rig_sim::PlannedOutage> planned;
    if (rig_sim::PlanOutages(rig_sim::OutagePlanConfig(), &copy, &planned, &err))
      for (const rig_sim::PlannedOutage& o : planned)
        std::printf(
            "make_bag: outage: turn away at %.2f s, looking down %.2f s, turn to cones %d and %d at %.2f s, held to "
            "%.2f s\n",
            o.away_start_s, o.away_s, o.cone_a, o.cone_b, o.pair_turn_s, o.pair_end_s);
  }
  rig_sim::ShortenScenario(duration, scale, &scenario);
  if (noise >= 0.0) scenario.render.noise_sigma_dn = noise;
  rig_sim::BagOptions opt;
  opt.compression = compression;
  opt.stream.camera_delay_s = delay_ms / 1000.0;
  rig_sim::BagStats stats;
  const auto t0 = std::chrono::steady_clock::now();
  if (!rig_sim::WriteScenarioBag(scenario, opt, output, &stats, &err)) {
    std::fprintf(stderr, "make_bag: %s\n", err.c_str());
    return 1;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "make_bag: %s (look %s) seed %llu: %.1f s, %llu images %dx%d, %llu IMU, %llu truth -> %s in %.1f s "
      "(rendering %.1f s)\n",
      scenario.name.c_str(), scenario.look.c_str(), static_cast<unsigned long long>(seed),
      scenario.trajectory.duration_s, static_cast<unsigned long long>(stats.images), scenario.camera.model.width_px,
      scenario.camera.model.height_px, static_cast<unsigned long long>(stats.imu),
      static_cast<unsigned long long>(stats.truth), output.c_str(), wall, stats.render_s);
  return 0;
}
