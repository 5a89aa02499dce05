// Surfaces and light of the ray caster (internal to rig_sim): procedural
// ground texture, Lambert + Phong shading under a sun whose strength and
// direction drift with time, sky, haze and the sRGB encoding.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "render_geometry.h"
#include "rig_sim/renderer.h"
#include "rig_sim/scene.h"

namespace rig_sim {

struct Lighting {
  Eigen::Vector3d sun_dir;  // unit, toward the sun, cones frame
  float sun = 0.8f;         // irradiance
  float ambient = 0.3f;
};

class Materials {
 public:
  Materials(const Scene& scene, const RenderConfig& config);
  Lighting LightingAt(double t_s) const;
  // Linear radiance seen along d (not unit) from o for the given hit.
  Eigen::Vector3f Shade(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Hit& hit, const Prim* decal,
                        const Lighting& light, int16_t* label) const;
  // Linear radiance -> sRGB 8-bit value.
  int Encode(float linear) const {
    const int i = static_cast<int>(linear * kLutScale);
    return lut_[i < 0 ? 0 : (i >= kLutSize ? kLutSize - 1 : i)];
  }

 private:
  static constexpr int kTexBits = 10;  // 1024 x 1024 texels
  static constexpr int kLutSize = 4096;
  static constexpr float kLutScale = 2048.0f;  // radiance 0..2
  float Texture(double x_m, double y_m) const;
  Eigen::Vector3f ConeAlbedo(const Prim& p, double z_m, bool* reflective) const;
  Eigen::Vector3f PersonAlbedo(double z_m, double height_m, bool* reflective) const;

  std::vector<ConeSpec> cones_;
  GroundStyle ground_;
  LightingConfig lighting_;
  std::vector<float> texture_;
  uint8_t lut_[kLutSize];
};

}  // namespace rig_sim
