// rosrun rig_sim validate_bag FILE.bag [--imu-rate HZ] [--camera-rate HZ] [--max-gap-factor F]
#include <cstdio>
#include <cstdlib>
#include <string>

#include "rig_sim/ros/bag_reader.h"

int main(int argc, char** argv) {
  rig_sim::ValidateConfig cfg;
  std::string path;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    double* number = a == "--imu-rate"         ? &cfg.imu_rate_hz
                     : a == "--camera-rate"    ? &cfg.camera_rate_hz
                     : a == "--max-gap-factor" ? &cfg.max_gap_factor
                                               : nullptr;
    if (a == "--help" || a == "-h") {
      std::printf(
          "usage: validate_bag FILE.bag [--imu-rate HZ] [--camera-rate HZ] [--max-gap-factor F]\n"
          "Checks topic rates, gaps, monotonic stamps, IMU norms at rest and that camera_info\n"
          "matches the images. Exit status 0 when every check passes, 1 otherwise (a bag that\n"
          "cannot be read, e.g. truncated, included), 2 for bad arguments.\n");
      return 0;
    } else if (number && has_value) {
      const std::string v = argv[++i];
      char* end = nullptr;
      *number = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != '\0' || !(*number > 0.0)) {
        std::fprintf(stderr, "validate_bag: %s needs a positive number, got '%s'\n", a.c_str(), v.c_str());
        return 2;
      }
    } else if (path.empty() && !a.empty() && a[0] != '-')
      path = a;
    else {
      std::fprintf(stderr, "validate_bag: bad argument '%s' (see --help)\n", a.c_str());
      return 2;
    }
  }
  if (path.empty()) {
    std::fprintf(stderr, "validate_bag: give a bag file (see --help)\n");
    return 2;
  }
  rig_sim::BagContents contents;
  std::string err;
  if (!rig_sim::ReadBagContents(path, rig_sim::TopicNames(), &contents, &err)) {
    std::fprintf(stderr, "validate_bag: %s\n", err.c_str());
    return 1;
  }
  const rig_sim::ValidationReport report = rig_sim::ValidateContents(contents, cfg);
  std::printf("%s%s: %s\n", report.Text().c_str(), path.c_str(), report.ok() ? "OK" : "FAILED");
  for (const rig_sim::Check& c : report.checks)
    if (!c.ok) std::fprintf(stderr, "validate_bag: %s: %s: %s\n", path.c_str(), c.name.c_str(), c.message.c_str());
  return report.ok() ? 0 : 1;
}
