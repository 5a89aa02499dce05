// The cone layout from YAML, in rig_sim's layout schema
// (src/rig_sim/config/layouts/*.yaml) so the simulator, bag replay and the rig
// share one file:
//   equilateral: {side_m: 1.5, height_m: 0.71, style: road}   # 3 cones, cone 1 on +x
//   cones:                                                    # and/or explicit cones
//     - {x_m: 1.0, y_m: 0.0, z_m: 0.0, height_m: 0.71, style: road, tau: 0.142857}
// Other keys (boxes, patches, people, ground, albedo, collars, ...) describe
// the simulated world and are ignored here. ROS-free.
#pragma once

#include <string>
#include <vector>

#include "cone_tracker/vision/cone_pose.h"

namespace cone_tracker {

struct LayoutLimits {
  int min_cones = 3;
  int max_cones = 8;
  double min_height_m = 0.10;  // 4" indoor cone
  double max_height_m = 0.91;  // 36" road cone
};

// Returns false with a message naming the file and the offending field; *cones untouched then.
bool LoadLayoutFile(const std::string& path, std::vector<ConeModel>* cones, std::string* error);
// The same on YAML text; `source` names it in messages.
bool ParseLayout(const std::string& yaml_text, const std::string& source, std::vector<ConeModel>* cones,
                 std::string* error);

}  // namespace cone_tracker
