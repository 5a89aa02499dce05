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
  std::string layout;          // file name in the layouts directory
  std::string look = "plain";  // ListLooks(): how the world and the camera look
  Scene scene;
  CameraConfig camera;
  TrajectoryConfig trajectory;
  ImuConfig imu;
  RenderConfig render;
  RenderConfig base_render;  // `render` before any look: the scenario's own lighting and noise
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

// Looks: named presets of the lighting, the appearance and the image noise (RenderConfig).
// "plain" (every scenario's default but `realistic`) renders exactly what rig_sim always rendered.
const std::vector<ScenarioInfo>& ListLooks();
// Sets s->render to look `name` over the scenario's own settings (s->base_render: a look replaces
// the previous one, "plain" restores them) and records it in s->look.
// Returns false with a message naming the known looks on an unknown name.
bool ApplyLook(const std::string& name, Scenario* s, std::string* error);

// Fits a scenario's walk to its scene after the layout changed (make_bag --layout): the `survey`
// walk circles the layout's cones 2.2 m outside the farthest one; `site_look_away` plans its outages
// on the layout (outage_plan.h); other scenarios are unchanged. Needs the seeds set (MakeScenario) and
// the full-size camera (before ShortenScenario). False with a message when the outages cannot be planned
// on the layout (*s keeps its previous segments then).
bool FitTrajectoryToScene(Scenario* s, std::string* error = nullptr);

// The scenario with a shorter duration and/or a smaller image (for samples and tests).
void ShortenScenario(double duration_s, double image_scale, Scenario* s);

}  // namespace rig_sim
