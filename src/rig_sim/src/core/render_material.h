// Surfaces and light of the ray caster (internal to rig_sim): procedural
// ground texture, Lambert + Phong shading under a sun whose strength and
// direction drift with time, sky, haze and the sRGB encoding.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "render_geometry.h"
#include "rig_sim/renderer.h"
#include "rig_sim/scene.h"

namespace rig_sim {

constexpr double kGroundTexelM = 0.02;

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
  // inv_norm_d = 1 / |d| (precomputed per pixel, since |d| does not change with the pose).
  // sun_visible: 1 in the sun, 0 in a cast shadow (used only with an active AppearanceConfig).
  Eigen::Vector3f Shade(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double inv_norm_d, const Hit& hit,
                        const Prim* decal, const Lighting& light, int16_t* label, float sun_visible = 1.0f) const;
  // Fast path for the commonest pixel, bare ground lit by `light` at point (x, y) and range r.
  Eigen::Vector3f ShadeGround(double x_m, double y_m, double range_m, const Lighting& light) const;
  // The same under an active AppearanceConfig: coloured sun and sky light, a cast shadow.
  Eigen::Vector3f ShadeGroundLook(double x_m, double y_m, double range_m, const Lighting& light,
                                  float sun_visible) const {
    const float sun = light.sun * static_cast<float>(std::max(0.0, light.sun_dir.z())) * sun_visible;
    const Eigen::Vector3f lit = sun_colour_ * sun + sky_colour_ * (light.ambient + 0.05f);
    return Haze(GroundAlbedo(x_m, y_m).cwiseProduct(lit), range_m, light);
  }
  bool look() const { return look_; }
  // Sky seen along a direction whose unit vector has vertical component up_z >= 0.
  Eigen::Vector3f ShadeSky(float up_z, const Lighting& light) const {
    const float up = std::min(1.0f, 2.0f * up_z);
    const Eigen::Vector3f horizon(0.70f, 0.76f, 0.85f), zenith(0.25f, 0.42f, 0.80f);
    return (horizon * (1.0f - up) + zenith * up) * (0.6f * light.sun + light.ambient);
  }
  // A row of linear radiances (3 per pixel) -> sRGB 8-bit values plus noise (may be null).
  // Split into simple loops so the compiler vectorises all but the table lookup.
  // shot_noise > 0 scales each noise sample by sqrt(1 + shot_noise * DN / 255) (AppearanceConfig).
  void EncodeRow(const float* linear, const int8_t* noise, int count, int16_t* scratch, uint8_t* out,
                 float shot_noise = 0.0f) const {
    const float top = static_cast<float>(kLutSize - 1);
    for (int k = 0; k < count; ++k)  // clamped both ways, so a bad lighting config cannot index outside lut_
      scratch[k] = static_cast<int16_t>(std::min(std::max(linear[k] * kLutScale, 0.0f), top));
    for (int k = 0; k < count; ++k) scratch[k] = lut_[scratch[k]];
    if (noise && shot_noise > 0.0f)
      for (int k = 0; k < count; ++k)
        scratch[k] = static_cast<int16_t>(
            scratch[k] + std::lround(noise[k] * std::sqrt(1.0f + shot_noise * scratch[k] * (1.0f / 255.0f))));
    else if (noise)
      for (int k = 0; k < count; ++k) scratch[k] = static_cast<int16_t>(scratch[k] + noise[k]);
    for (int k = 0; k < count; ++k) out[k] = static_cast<uint8_t>(std::clamp<int16_t>(scratch[k], 0, 255));
  }

 private:
  static constexpr int kTexBits = 9;    // 512 x 512 texels, one byte each: stays in cache
  static constexpr int kMacroBits = 6;  // 64 x 64 coarse variation
  static constexpr int kLutSize = 4096;
  static constexpr float kLutScale = 2048.0f;  // radiance 0..2
  float Texture(double x_m, double y_m) const;
  Eigen::Vector3f GroundAlbedo(double x_m, double y_m) const;
  Eigen::Vector3f Haze(const Eigen::Vector3f& radiance, double range_m, const Lighting& light) const;
  Eigen::Vector3f ConeAlbedo(const Prim& p, const Eigen::Vector3d& hit_m, bool* reflective) const;
  // Dirt on cone i at a point of its surface: its weathering there, in [0, 1].
  float ConeDirt(int cone_index, const Eigen::Vector3d& hit_m, double height_fraction) const;
  Eigen::Vector3f PersonAlbedo(double z_m, double height_m, bool* reflective) const;
  Eigen::Vector3f PlatformAlbedo(const Prim& p, const Eigen::Vector3d& hit_m, const Eigen::Vector3d& normal) const;

  std::vector<ConeSpec> cones_;
  std::vector<PlatformSpec> platforms_;
  GroundStyle ground_;
  LightingConfig lighting_;
  bool look_ = false;  // an AppearanceConfig other than the default
  Eigen::Vector3f sun_colour_ = Eigen::Vector3f::Ones(), sky_colour_ = Eigen::Vector3f::Ones();
  std::vector<float> cone_weathering_;  // per cone
  uint64_t dirt_seed_ = 0;
  std::vector<uint8_t> texture_;
  std::vector<float> macro_;
  uint8_t lut_[kLutSize];
};

// Inline: these run for most pixels of every frame.
inline float Materials::Texture(double x, double y) const {
  // Truncation of a positive number is floor: the offset keeps it positive within 20 km.
  constexpr double kOffset = 1 << 20;
  const int mask = (1 << kTexBits) - 1, macro_mask = (1 << kMacroBits) - 1;
  const int ix = static_cast<int>(x * (1.0 / kGroundTexelM) + kOffset) & mask;
  const int iy = static_cast<int>(y * (1.0 / kGroundTexelM) + kOffset) & mask;
  // A second, coarser texture at an unrelated scale (0.37 m cells) hides the tiling.
  const int jx = static_cast<int>(x * (1.0 / 0.37) + kOffset) & macro_mask;
  const int jy = static_cast<int>(y * (1.0 / 0.37) + kOffset) & macro_mask;
  return texture_[(iy << kTexBits) | ix] * (1.0f / 128.0f) * macro_[(jy << kMacroBits) | jx];
}

inline Eigen::Vector3f Materials::Haze(const Eigen::Vector3f& radiance, double range_m, const Lighting& light) const {
  if (range_m <= 25.0) return radiance;
  // Haze toward the horizon; x / (1 + x) is cheaper than 1 - exp(-x) and has the same shape.
  const double x = (range_m - 25.0) / 60.0;
  const float fog = static_cast<float>(x / (1.0 + x));
  return radiance * (1.0f - fog) + Eigen::Vector3f(0.55f, 0.58f, 0.62f) * ((0.6f * light.sun + light.ambient) * fog);
}

inline Eigen::Vector3f Materials::GroundAlbedo(double x, double y) const {
  const float tex = Texture(x, y);
  switch (ground_) {
    case GroundStyle::kGrass:
      return Eigen::Vector3f(0.06f, 0.13f, 0.03f) * tex;
    case GroundStyle::kConcrete: {
      // Expansion joints every 2 m, 2 cm wide.
      const double fx = x * 0.5 + 4096.0, fy = y * 0.5 + 4096.0;
      const double jx = fx - static_cast<int>(fx), jy = fy - static_cast<int>(fy);
      const bool joint = jx < 0.005 || jx > 0.995 || jy < 0.005 || jy > 0.995;
      return Eigen::Vector3f(0.30f, 0.29f, 0.27f) * (tex * (joint ? 0.4f : 1.0f));
    }
    default:
      return Eigen::Vector3f(0.10f, 0.10f, 0.11f) * tex;
  }
}

inline Eigen::Vector3f Materials::ShadeGround(double x, double y, double range_m, const Lighting& light) const {
  const float lit = light.sun * static_cast<float>(std::max(0.0, light.sun_dir.z())) + light.ambient + 0.05f;
  return Haze(GroundAlbedo(x, y) * lit, range_m, light);
}

}  // namespace rig_sim
