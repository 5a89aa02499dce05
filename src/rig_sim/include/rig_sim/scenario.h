// Named scenarios: a layout, a camera, a motion, an IMU and lighting, all
// derived deterministically from (name, seed). ROS-free.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rig_sim/camera_model.h"
#include "rig_sim/imu_model.h"
#include "rig_sim/renderer.h"
#include "rig_sim/scene.h"
#include "rig_sim/trajectory.h"

namespace rig_sim {

struct Scenario {
  std::string name;
  std::string description;
  std::string layout;  // file name in the layouts directory
  Scene scene;
  CameraConfig camera;
  TrajectoryConfig trajectory;
  ImuConfig imu;
  RenderConfig render;
};

struct ScenarioInfo {
  std::string name;
  std::string description;
};
const std::vector<ScenarioInfo>& ListScenarios();

// Builds scenario `name` for `seed`, loading its layout from layouts_dir.
// Returns false with a message on an unknown name or a bad layout.
bool MakeScenario(const std::string& name, uint64_t seed, const std::string& layouts_dir, Scenario* out,
                  std::string* error);

// The scenario with a shorter duration and/or a smaller image (for samples and tests).
void ShortenScenario(double duration_s, double image_scale, Scenario* s);

}  // namespace rig_sim
