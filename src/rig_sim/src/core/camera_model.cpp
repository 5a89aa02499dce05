#include "rig_sim/camera_model.h"

#include <sstream>

namespace rig_sim {

CameraConfig CameraConfig::Scaled(double factor) const {
  CameraConfig c = *this;
  c.model = model.Scaled(factor);
  return c;
}

std::string CameraConfig::Validate() const {
  std::ostringstream err;
  if (model.width_px < 8 || model.height_px < 8)
    err << "width_px/height_px must be in [8, 8192], got " << model.width_px << "x" << model.height_px;
  else if (!rig_model::Validate(model).empty())
    err << rig_model::Validate(model);
  else if (!(rate_hz > 0.0))
    err << "rate_hz must be positive";
  return err.str();
}

}  // namespace rig_sim
