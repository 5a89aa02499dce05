// rosrun rig_sim make_layout --cones N --seed S --output LAYOUT.yaml [--spacing M] [--side M]
// A random layout of N cones of mixed heights (random_layout.h), for survey walks and tests.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>

#include "rig_model/surveyed_layout.h"
#include "rig_sim/random_layout.h"

int main(int argc, char** argv) {
  rig_sim::RandomLayoutConfig config;
  std::string output;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      std::printf(
          "usage: make_layout --cones N --seed S --output LAYOUT.yaml [--spacing M] [--side M]\n"
          "A random layout: N cones (3..30) of 0.30/0.46 m (plain) and 0.71/0.91 m (road), at least --spacing\n"
          "(default 1 m) apart in a square of --side metres (default: 1.3 m x sqrt(N), at least 3 m), centred\n"
          "on their centroid. Cones 0 and 1 have heights no other cone has (a survey's origin and +x).\n");
      return 0;
    }
    if (i + 1 >= argc) {
      std::fprintf(stderr, "make_layout: %s needs a value (see --help)\n", a.c_str());
      return 2;
    }
    const std::string v = argv[++i];
    try {
      if (a == "--cones")
        config.cones = std::stoi(v);
      else if (a == "--seed")
        config.seed = std::stoull(v);
      else if (a == "--spacing")
        config.min_spacing_m = std::stod(v);
      else if (a == "--side")
        config.side_m = std::stod(v);
      else if (a == "--output" || a == "-o")
        output = v;
      else {
        std::fprintf(stderr, "make_layout: unknown argument '%s' (see --help)\n", a.c_str());
        return 2;
      }
    } catch (const std::exception&) {
      std::fprintf(stderr, "make_layout: bad value '%s' for %s\n", v.c_str(), a.c_str());
      return 2;
    }
  }
  if (output.empty()) {
    std::fprintf(stderr, "make_layout: --output LAYOUT.yaml is required (see --help)\n");
    return 2;
  }
  try {
    const rig_sim::Scene scene = rig_sim::RandomLayout(config);
    std::ofstream out(output);
    out << "# make_layout --cones " << config.cones << " --seed " << config.seed << "\n"
        << rig_model::ConesYaml(scene.cones);
    if (!out) throw std::runtime_error(output + ": cannot write");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_layout: %s\n", e.what());
    return 1;
  }
  std::printf("make_layout: %d cones, seed %llu -> %s\n", config.cones, static_cast<unsigned long long>(config.seed),
              output.c_str());
  return 0;
}
