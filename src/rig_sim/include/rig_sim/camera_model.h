// The simulated camera: rig_model's camera model (pinhole + plumb_bob, the thesis's 3.10) and the
// frame rate. The default is the thesis's rig (rig_model::ThesisCamera). ROS-free.
#pragma once

#include <string>

#include "rig_model/camera_model.h"

namespace rig_sim {

struct CameraConfig {
  rig_model::CameraModel model = rig_model::ThesisCamera();
  double rate_hz = 30.0;

  // The same lens on a sensor scaled by `factor` (e.g. 0.25 for 256x192).
  CameraConfig Scaled(double factor) const;
  // Empty when valid, else a message naming the bad field.
  std::string Validate() const;
};

}  // namespace rig_sim
