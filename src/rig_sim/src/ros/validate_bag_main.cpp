// rosrun rig_sim validate_bag FILE.bag [--imu-rate HZ] [--camera-rate HZ] [--max-gap-factor F]
#include <cstdio>
#include <string>

#include "rig_sim/ros/bag_reader.h"

int main(int argc, char** argv) {
  rig_sim::ValidateConfig cfg;
  std::string path;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--help" || a == "-h") {
      std::printf(
          "usage: validate_bag FILE.bag [--imu-rate HZ] [--camera-rate HZ] [--max-gap-factor F]\n"
          "Checks topic rates, gaps, monotonic stamps, IMU norms at rest and that camera_info\n"
          "matches the images. Exit status 0 when every check passes, 1 otherwise.\n");
      return 0;
    } else if (a == "--imu-rate" && has_value)
      cfg.imu_rate_hz = std::stod(argv[++i]);
    else if (a == "--camera-rate" && has_value)
      cfg.camera_rate_hz = std::stod(argv[++i]);
    else if (a == "--max-gap-factor" && has_value)
      cfg.max_gap_factor = std::stod(argv[++i]);
    else if (path.empty() && a[0] != '-')
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
  return report.ok() ? 0 : 1;
}
