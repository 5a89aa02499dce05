// Random cone layouts for the survey tests (cone_survey) and `make_layout`: n cones of mixed
// heights at random positions, seeded. ROS-free.
#pragma once

#include <cstdint>
#include <string>

#include "rig_sim/scene.h"

namespace rig_sim {

struct RandomLayoutConfig {
  int cones = 8;  // 3 to 30 (rig_model's limits)
  uint64_t seed = 1;
  double min_spacing_m = 1.0;  // between any two bases
  // Side of the square the bases are drawn in; 0: 1.3 m per sqrt(cone) (4 m for 9 cones), at least 3 m.
  double side_m = 0.0;
  std::string Validate() const;  // "" or what is wrong, naming the field
};

// Cones of 0.30 and 0.46 m (plain) and 0.71 and 0.91 m (road): cones 0 and 1 have heights no
// other cone has (a survey inventory can name them as origin and +x), the others share the remaining
// two heights. The bases' centroid is the origin (the `cones` frame). Throws std::invalid_argument
// with Validate()'s message.
Scene RandomLayout(const RandomLayoutConfig& config);

}  // namespace rig_sim
