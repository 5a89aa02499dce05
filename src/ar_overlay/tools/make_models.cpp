// Writes the project's generated models (mesh_generators.h) as PLY files into
// a folder: the peaks surface, the cargo aircraft and the KR6 arm's links.
// Usage: ar_overlay_make_models <output folder>
#include <cstdio>
#include <exception>
#include <string>

#include "ar_overlay/mesh_generators.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <output folder>\n", argv[0]);
    return 2;
  }
  const std::string dir = std::string(argv[1]) + "/";
  try {
    ar_overlay::WritePly(ar_overlay::PeaksSurface(49), dir + "peaks.ply");
    ar_overlay::WritePly(ar_overlay::CargoAircraft(), dir + "c130.ply");
    for (const auto& link : ar_overlay::Kr6Arm()) ar_overlay::WritePly(link.mesh, dir + link.name + ".ply");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ar_overlay_make_models: %s\n", e.what());
    return 1;
  }
  return 0;
}
