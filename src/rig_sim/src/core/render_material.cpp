#include "render_material.h"

#include "angles.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace rig_sim {
namespace {

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

uint64_t Mix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Uniform in [0, 1) from a hash.
float Unit(uint64_t h) { return static_cast<float>(h >> 40) * (1.0f / 16777216.0f); }

// Trilinear value noise in [0, 1) on a lattice of `cell_m`.
float ValueNoise3(const Eigen::Vector3d& p, double cell_m, uint64_t seed) {
  const Eigen::Vector3d f = p / cell_m + Eigen::Vector3d::Constant(4096.0);
  const int64_t ix = static_cast<int64_t>(f.x()), iy = static_cast<int64_t>(f.y()), iz = static_cast<int64_t>(f.z());
  const float ax = static_cast<float>(f.x() - ix), ay = static_cast<float>(f.y() - iy),
              az = static_cast<float>(f.z() - iz);
  auto at = [&](int64_t i, int64_t j, int64_t k) {
    return Unit(Mix(seed ^ Mix(static_cast<uint64_t>(i) * 73856093ull ^ static_cast<uint64_t>(j) * 19349663ull ^
                               static_cast<uint64_t>(k) * 83492791ull)));
  };
  float v = 0.0f;
  for (int dk = 0; dk < 2; ++dk)
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di)
        v += (di ? ax : 1 - ax) * (dj ? ay : 1 - ay) * (dk ? az : 1 - az) * at(ix + di, iy + dj, iz + dk);
  return v;
}

}  // namespace

bool AppearanceConfig::Active() const {
  return shadows || sun_colour != Eigen::Vector3d::Ones() || sky_colour != Eigen::Vector3d::Ones() ||
         cone_weathering != 0.0 || white_balance_gain != Eigen::Vector3d::Ones() || white_balance_drift != 0.0 ||
         exposure_drift != 0.0 || shot_noise != 0.0 || vignetting != 0.0 || exposure_time_s != 0.0 || blur_samples != 1;
}

std::string AppearanceConfig::Validate() const {
  auto colour_ok = [](const Eigen::Vector3d& c) { return c.minCoeff() >= 0.0 && c.maxCoeff() <= 4.0; };
  if (!colour_ok(sun_colour)) return "sun_colour: each channel must be in [0, 4]";
  if (!colour_ok(sky_colour)) return "sky_colour: each channel must be in [0, 4]";
  if (!colour_ok(white_balance_gain)) return "white_balance_gain: each channel must be in [0, 4]";
  if (!(cone_weathering >= 0.0 && cone_weathering <= 1.0)) return "cone_weathering must be in [0, 1]";
  if (!(white_balance_drift >= 0.0 && white_balance_drift < 1.0)) return "white_balance_drift must be in [0, 1)";
  if (!(exposure_drift >= 0.0 && exposure_drift < 1.0)) return "exposure_drift must be in [0, 1)";
  if (!(drift_period_s > 0.0)) return "drift_period_s must be positive";
  if (!(shot_noise >= 0.0 && shot_noise <= 100.0)) return "shot_noise must be in [0, 100]";
  if (!(vignetting >= 0.0 && vignetting < 1.0)) return "vignetting must be in [0, 1)";
  if (!(exposure_time_s >= 0.0 && exposure_time_s <= 0.1)) return "exposure_time_s must be in [0, 0.1] s";
  if (blur_samples < 1 || blur_samples > 64) return "blur_samples must be in [1, 64]";
  return "";
}

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
  const AppearanceConfig& a = config.appearance;
  look_ = a.Active();
  sun_colour_ = a.sun_colour.cast<float>();
  sky_colour_ = a.sky_colour.cast<float>();
  dirt_seed_ = Mix(config.seed ^ 0x6469727479ull);
  for (size_t i = 0; i < cones_.size(); ++i)  // each cone its own share of the weathering
    cone_weathering_.push_back(static_cast<float>(a.cone_weathering) * (0.4f + 0.6f * Unit(Mix(dirt_seed_ + i))));
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

float Materials::ConeDirt(int i, const Eigen::Vector3d& q, double f) const {
  // Mottled at ~3 cm and ~10 cm, heavier toward the base (splashes from the road).
  const float mottle =
      0.65f * ValueNoise3(q, 0.03, dirt_seed_ + 2 * i) + 0.35f * ValueNoise3(q, 0.10, dirt_seed_ + 2 * i + 1);
  const float low = static_cast<float>(std::clamp(1.0 - f, 0.0, 1.0));
  const float dirt = cone_weathering_[i] * (0.55f + 0.8f * low * low) * (0.15f + 1.7f * mottle);
  return std::clamp(dirt, 0.0f, 1.0f);
}

Eigen::Vector3f Materials::ConeAlbedo(const Prim& p, const Eigen::Vector3d& q, bool* reflective) const {
  const ConeSpec& c = cones_[p.cone_index];
  const double f = (q.z() - c.base_m.z()) / c.height_m;
  Eigen::Vector3f albedo = p.albedo;
  *reflective = false;
  for (const auto& band : c.collars)
    if (f >= band.first && f <= band.second) {
      *reflective = true;
      albedo = Eigen::Vector3f(0.80f, 0.80f, 0.78f);
      break;
    }
  if (!look_ || cone_weathering_[p.cone_index] <= 0.0f) return albedo;
  const float dirt = ConeDirt(p.cone_index, q, f);
  if (*reflective)  // grimy collars: grey-brown
    return albedo * (1.0f - 0.6f * dirt) + Eigen::Vector3f(0.22f, 0.19f, 0.15f) * (0.6f * dirt);
  // Faded and dirty orange: less saturated (toward its own luminance), darker, hue toward brown.
  const float lum = 0.2126f * albedo.x() + 0.7152f * albedo.y() + 0.0722f * albedo.z();
  albedo = albedo * (1.0f - 0.5f * dirt) + Eigen::Vector3f::Constant(lum) * (0.5f * dirt);
  return albedo * (1.0f - 0.7f * dirt) + Eigen::Vector3f(0.12f, 0.07f, 0.035f) * (0.7f * dirt);
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
                                 const Prim* decal, const Lighting& light, int16_t* label, float sun_visible) const {
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
        albedo = ConeAlbedo(*hit.prim, p, &reflective);
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
  if (look_) {  // coloured sun and sky, cast shadows
    const float sun = light.sun * lambert * sun_visible;
    Eigen::Vector3f radiance = albedo.cwiseProduct(sun_colour_ * sun + sky_colour_ * (sky + 0.05f));
    if (shine > 0.0f || reflective) {
      const Eigen::Vector3d r = dn - 2.0 * dn.dot(n) * n;
      const float spec = static_cast<float>(std::pow(std::max(0.0, r.dot(light.sun_dir)), 24.0));
      radiance += sun_colour_ * ((shine + (reflective ? 0.3f : 0.0f)) * light.sun * sun_visible * spec);
      if (reflective) radiance += albedo * 0.25f * static_cast<float>(std::max(0.0, -dn.dot(n)));
    }
    return Haze(radiance, hit.t / inv_norm_d, light);
  }
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
