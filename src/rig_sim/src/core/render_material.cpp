#include "render_material.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace rig_sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Value noise on a lattice of `period` texels, bilinear, periodic over the texture.
void AddValueNoise(std::vector<float>* tex, int size, int period, float amplitude, std::mt19937* rng) {
  const int cells = size / period;
  std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
  std::vector<float> lattice(cells * cells);
  for (auto& v : lattice) v = uni(*rng);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const float fx = static_cast<float>(x) / period, fy = static_cast<float>(y) / period;
      const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
      const float ax = fx - x0, ay = fy - y0;
      auto at = [&](int i, int j) { return lattice[(j % cells) * cells + (i % cells)]; };
      const float v = (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x0 + 1, y0)) +
                      ay * ((1 - ax) * at(x0, y0 + 1) + ax * at(x0 + 1, y0 + 1));
      (*tex)[y * size + x] += amplitude * v;
    }
}

}  // namespace

Materials::Materials(const Scene& scene, const RenderConfig& config)
    : cones_(scene.cones), platforms_(scene.platforms), ground_(scene.ground), lighting_(config.lighting) {
  const int size = 1 << kTexBits;
  std::vector<float> tex(size * size, 1.0f);
  std::mt19937 rng(12345u + static_cast<unsigned>(scene.ground));  // the ground looks the same for every seed
  AddValueNoise(&tex, size, 128, 0.15f, &rng);
  AddValueNoise(&tex, size, 32, 0.12f, &rng);
  AddValueNoise(&tex, size, 8, 0.10f, &rng);
  AddValueNoise(&tex, size, 2, 0.08f, &rng);
  std::uniform_real_distribution<float> grain(-0.12f, 0.12f);
  texture_.resize(tex.size());
  for (size_t i = 0; i < tex.size(); ++i)
    texture_[i] = static_cast<uint8_t>(std::clamp(std::lround(128.0f * (tex[i] + grain(rng))), 26l, 255l));
  const int macro_size = 1 << kMacroBits;
  macro_.assign(macro_size * macro_size, 1.0f);
  AddValueNoise(&macro_, macro_size, 16, 0.25f, &rng);
  AddValueNoise(&macro_, macro_size, 4, 0.1f, &rng);
  for (int i = 0; i < kLutSize; ++i) {
    const double x = std::min(1.0, i / static_cast<double>(kLutScale));
    const double s = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    lut_[i] = static_cast<uint8_t>(std::lround(255.0 * s));
  }
}

Lighting Materials::LightingAt(double t) const {
  const LightingConfig& c = lighting_;
  const double w = 2.0 * kPi / c.variation_period_s;
  // Passing clouds: two incommensurate swings of the sun's strength.
  const double swing = 0.6 * std::sin(w * t) + 0.4 * std::sin(2.7 * w * t + 1.3);
  const double el = c.sun_elevation_deg * kPi / 180.0;
  const double az = (c.sun_azimuth_deg + c.azimuth_drift_deg_s * t) * kPi / 180.0;
  Lighting l;
  l.sun_dir = Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  l.sun = static_cast<float>(std::max(0.0, c.sun_irradiance * (1.0 + c.variation * swing)));
  l.ambient = static_cast<float>(c.ambient * (1.0 + 0.3 * c.variation * swing));
  return l;
}

Eigen::Vector3f Materials::ConeAlbedo(const Prim& p, double z, bool* reflective) const {
  const ConeSpec& c = cones_[p.cone_index];
  const double f = (z - c.base_m.z()) / c.height_m;
  for (const auto& band : c.collars)
    if (f >= band.first && f <= band.second) {
      *reflective = true;
      return Eigen::Vector3f(0.80f, 0.80f, 0.78f);
    }
  *reflective = false;
  return p.albedo;
}

Eigen::Vector3f Materials::PersonAlbedo(double z, double h, bool* reflective) const {
  const double f = z / h;
  *reflective = false;
  if (f < 0.5) return Eigen::Vector3f(0.03f, 0.04f, 0.08f);   // dark trousers
  if (f > 0.86) return Eigen::Vector3f(0.45f, 0.25f, 0.16f);  // head
  if ((f > 0.60 && f < 0.64) || (f > 0.72 && f < 0.76)) {     // silver vest stripes
    *reflective = true;
    return Eigen::Vector3f(0.7f, 0.7f, 0.7f);
  }
  return Eigen::Vector3f(0.95f, 0.30f, 0.02f);  // hi-vis orange
}

Eigen::Vector3f Materials::PlatformAlbedo(const Prim& prim, const Eigen::Vector3d& hit_m,
                                          const Eigen::Vector3d& normal) const {
  if (normal.z() < 0.5) return prim.albedo;  // the sides carry no dots
  const PlatformSpec& pl = platforms_[static_cast<size_t>(prim.platform_index)];
  const double dx = hit_m.x() - prim.origin.x(), dy = hit_m.y() - prim.origin.y();
  // Board frame (rotation by -yaw), then grid units with dot (0, 0) at integer (0, 0).
  const double gx = (prim.cos_yaw * dx + prim.sin_yaw * dy) / pl.spacing_m + 0.5 * (pl.cols - 1);
  const double gy = (-prim.sin_yaw * dx + prim.cos_yaw * dy) / pl.spacing_m + 0.5 * (pl.rows - 1);
  const double kx = std::round(gx), ky = std::round(gy);
  if (kx < 0 || ky < 0 || kx > pl.cols - 1 || ky > pl.rows - 1) return prim.albedo;
  const double ex = (gx - kx) * pl.spacing_m, ey = (gy - ky) * pl.spacing_m;
  return ex * ex + ey * ey <= pl.dot_radius_m * pl.dot_radius_m ? pl.dot_albedo.cast<float>() : prim.albedo;
}

Eigen::Vector3f Materials::Shade(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double inv_norm_d, const Hit& hit,
                                 const Prim* decal, const Lighting& light, int16_t* label) const {
  const Eigen::Vector3d dn = d * inv_norm_d;
  if (hit.prim == nullptr && d.z() >= 0.0) {
    *label = kLabelSky;
    return ShadeSky(static_cast<float>(dn.z()), light);
  }
  const Eigen::Vector3d p = o + hit.t * d;
  Eigen::Vector3f albedo;
  Eigen::Vector3d n = hit.normal;
  bool reflective = false;
  float shine = 0.0f;
  if (hit.prim == nullptr) {  // ground
    n = Eigen::Vector3d::UnitZ();
    const float tex = Texture(p.x(), p.y());
    if (decal) {
      *label = decal->label;
      albedo = decal->albedo * (0.9f + 0.1f * tex);
    } else {
      *label = kLabelGround;
      albedo = GroundAlbedo(p.x(), p.y());
    }
  } else {
    *label = hit.prim->label;
    switch (hit.prim->kind) {
      case PrimKind::kCone:
        albedo = ConeAlbedo(*hit.prim, p.z(), &reflective);
        shine = 0.25f;
        break;
      case PrimKind::kCylinder:
        albedo = PersonAlbedo(p.z(), hit.prim->height, &reflective);
        break;
      default:
        albedo = hit.prim->platform_index >= 0 ? PlatformAlbedo(*hit.prim, p, n) : hit.prim->albedo;
        shine = 0.05f;
        break;
    }
  }
  const float lambert = static_cast<float>(std::max(0.0, n.dot(light.sun_dir)));
  // Sky light on a tilted surface: the visible fraction of the sky hemisphere.
  const float sky = light.ambient * static_cast<float>(0.5 + 0.5 * n.z());
  Eigen::Vector3f radiance = albedo * (light.sun * lambert + sky + 0.05f);
  if (shine > 0.0f || reflective) {
    const Eigen::Vector3d r = dn - 2.0 * dn.dot(n) * n;  // mirror direction
    const float spec = static_cast<float>(std::pow(std::max(0.0, r.dot(light.sun_dir)), 24.0));
    radiance += Eigen::Vector3f::Constant((shine + (reflective ? 0.3f : 0.0f)) * light.sun * spec);
    if (reflective) radiance += albedo * 0.25f * static_cast<float>(std::max(0.0, -dn.dot(n)));  // retroreflection
  }
  return Haze(radiance, hit.t / inv_norm_d, light);
}

}  // namespace rig_sim
