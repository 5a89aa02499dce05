// ekf_replay's trajectory file (TUM: t x y z qx qy qz qw a line), for the replay tests.
#pragma once

#include <cmath>
#include <fstream>
#include <map>
#include <string>

#include "pose_math/pose.h"

namespace pose_ekf_test {

// Milliseconds since t0_s -> pose.
inline std::map<long, pose_math::Pose> ReadTum(const std::string& path, double t0_s) {
  std::map<long, pose_math::Pose> out;
  std::ifstream f(path);
  double t, x, y, z, qx, qy, qz, qw;
  while (f >> t >> x >> y >> z >> qx >> qy >> qz >> qw)
    out[std::lround((t - t0_s) * 1000)] = {pose_math::Quat(qw, qx, qy, qz), Eigen::Vector3d(x, y, z)};
  return out;
}

}  // namespace pose_ekf_test
