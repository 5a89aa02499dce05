// Writes the project's generated models (mesh_generators.h) as PLY files into
// a folder: the peaks surface, the cargo aircraft, the KR6 arm's links and
// the overlay test platform's red dots.
// Usage: ar_overlay_make_models <output folder>
#include <cstdio>
#include <exception>
#include <string>

#include "ar_overlay/core/mesh_generators.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <output folder>\n", argv[0]);
    return 2;
  }
  const std::string dir = std::string(argv[1]) + "/";
  try {
    ar_overlay::WritePly(ar_overlay::PeaksSurface(49), dir + "peaks.ply");
    ar_overlay::WritePly(ar_overlay::CargoAircraft(), dir + "c130.ply");
    // 7.2's virtual object: red dots between the platform's 5 x 5 blue ones (rig_sim platform.yaml).
    ar_overlay::WritePly(ar_overlay::DotGrid(4, 4, 0.1f, 0.015f, 24, {1, 0, 0, 1}), dir + "platform_red_dots.ply");
    for (const auto& link : ar_overlay::Kr6Arm()) ar_overlay::WritePly(link.mesh, dir + link.name + ".ply");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ar_overlay_make_models: %s\n", e.what());
    return 1;
  }
  return 0;
}
