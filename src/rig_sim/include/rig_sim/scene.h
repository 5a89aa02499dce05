// The simulated world in the `cones` frame {M}: the cone layout of rig_model (the one schema and
// parser of config/layouts/*.yaml: cones, and the scenery around them). ROS-free.
#pragma once

#include <string>

#include "rig_model/layout.h"

namespace rig_sim {

using rig_model::BoxSpec;
using rig_model::ConeSpec;
using rig_model::ConeStyle;
using rig_model::GroundStyle;
using rig_model::MakeCone;
using rig_model::PatchSpec;
using rig_model::PersonSpec;
using rig_model::PlatformSpec;
using Scene = rig_model::Layout;

// The thesis's layout (3.1.3): three identical cones in an equilateral triangle, centred on the
// origin, cone 1 on +x.
inline Scene EquilateralScene(double side_m, double height_m, ConeStyle style) {
  return rig_model::EquilateralLayout(side_m, height_m, style);
}
// Default: three 28" (0.71 m) road cones, 1.5 m apart.
inline Scene DefaultScene() { return rig_model::DefaultLayout(); }

// Layout files through rig_model::LoadLayoutFile. Returns false with its message (file, line,
// field) on any error; *scene is untouched then.
bool LoadSceneYaml(const std::string& path, Scene* scene, std::string* error);
bool ParseSceneYaml(const std::string& text, Scene* scene, std::string* error);

}  // namespace rig_sim
