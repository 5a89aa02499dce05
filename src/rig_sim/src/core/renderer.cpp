#include "rig_sim/renderer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>
#include <stdexcept>
#include <thread>

#include "angles.h"
#include "render_geometry.h"
#include "render_material.h"

namespace rig_sim {
namespace {

constexpr int kTile = 16;

uint64_t SplitMix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

}  // namespace

struct Renderer::Impl {
  rig_model::CameraModel camera;
  RenderConfig config;
  std::vector<Prim> prims;
  Materials materials;
  int width, height, tiles_x, tiles_y;
  std::vector<Eigen::Vector3d> rays;       // per pixel, camera frame, z = 1 (exact undistortion)
  std::vector<double> inv_norms;           // 1 / |ray|
  std::vector<Eigen::Vector3f> rays_f;     // the same rays in single precision, for bare ground
  std::vector<float> norms_f;              // |ray|
  std::vector<Eigen::Vector3d> tile_axis;  // unit, camera frame
  std::vector<double> tile_half_angle;     // rad, bounds every pixel ray of the tile
  std::vector<int8_t> noise;               // N(0, sigma) samples
  std::vector<float> vignette;             // per pixel gain, empty without vignetting
  static constexpr uint32_t kNoiseMask = (1u << 20) - 1;

  Impl(const rig_model::CameraModel& cam, const Scene& scene, const RenderConfig& cfg)
      : camera(cam),
        config(cfg),
        prims(BuildPrims(scene)),
        materials(scene, cfg),
        width(cam.width_px),
        height(cam.height_px) {
    tiles_x = (width + kTile - 1) / kTile;
    tiles_y = (height + kTile - 1) / kTile;
    rays.resize(static_cast<size_t>(width) * height);
    for (int v = 0; v < height; ++v)
      for (int u = 0; u < width; ++u) rays[static_cast<size_t>(v) * width + u] = camera.PixelRay(u, v);
    inv_norms.resize(rays.size());
    rays_f.resize(rays.size());
    norms_f.resize(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
      inv_norms[i] = 1.0 / rays[i].norm();
      rays_f[i] = rays[i].cast<float>();
      norms_f[i] = static_cast<float>(rays[i].norm());
    }
    tile_axis.resize(tiles_x * tiles_y);
    tile_half_angle.resize(tiles_x * tiles_y);
    for (int ty = 0; ty < tiles_y; ++ty)
      for (int tx = 0; tx < tiles_x; ++tx) {
        const int u0 = tx * kTile, v0 = ty * kTile;
        const int u1 = std::min(width, u0 + kTile), v1 = std::min(height, v0 + kTile);
        Eigen::Vector3d axis = Eigen::Vector3d::Zero();
        for (int v = v0; v < v1; ++v)
          for (int u = u0; u < u1; ++u) axis += rays[v * width + u].normalized();
        axis.normalize();
        double max_angle = 0.0;
        for (int v = v0; v < v1; ++v)
          for (int u = u0; u < u1; ++u)
            max_angle = std::max(max_angle, std::acos(std::min(1.0, axis.dot(rays[v * width + u].normalized()))));
        tile_axis[ty * tiles_x + tx] = axis;
        tile_half_angle[ty * tiles_x + tx] = max_angle + 1e-6;
      }
    if (!(cfg.exposure >= 0.0) || !(cfg.noise_sigma_dn >= 0.0) || cfg.noise_sigma_dn > 50.0)
      throw std::invalid_argument("RenderConfig: exposure must be >= 0 and noise_sigma_dn in [0, 50]");
    const std::string look_error = cfg.appearance.Validate();
    if (!look_error.empty()) throw std::invalid_argument("RenderConfig.appearance: " + look_error);
    if (cfg.appearance.vignetting > 0.0) {
      const double cx = 0.5 * (width - 1), cy = 0.5 * (height - 1), r2max = cx * cx + cy * cy;
      vignette.resize(rays.size());
      for (int v = 0; v < height; ++v)
        for (int u = 0; u < width; ++u) {
          const double s2 = ((u - cx) * (u - cx) + (v - cy) * (v - cy)) / r2max;
          vignette[static_cast<size_t>(v) * width + u] =
              static_cast<float>(1.0 - cfg.appearance.vignetting * s2 * (1.5 - 0.5 * s2));
        }
    }
    noise.resize(kNoiseMask + 1 + 3 * static_cast<size_t>(width));  // a row never wraps
    std::mt19937_64 rng(SplitMix64(cfg.seed ^ 0x6e6f697365ull));
    std::normal_distribution<double> normal(0.0, std::max(0.0, cfg.noise_sigma_dn));
    for (auto& n : noise) n = static_cast<int8_t>(std::clamp(std::lround(normal(rng)), -127l, 127l));
  }

  // Per tile in [first, end), the primitives whose bounding sphere may meet one of its rays.
  std::vector<std::vector<const Prim*>> CullTiles(const TruePose& pose, int first, int end) const {
    std::vector<std::vector<const Prim*>> lists(end - first);
    for (const Prim& p : prims) {
      const Eigen::Vector3d q = pose.R_cones_camera.transpose() * (p.sphere_center - pose.p_camera_in_cones_m);
      const double dist = q.norm();
      const bool inside = dist <= p.sphere_radius;
      const double gamma = inside ? kPi : std::asin(p.sphere_radius / dist);
      const Eigen::Vector3d qn = inside ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d(q / dist);
      for (int i = first; i < end; ++i) {
        const double angle = std::acos(std::clamp(qn.dot(tile_axis[i]), -1.0, 1.0));
        if (!config.tile_culling || inside || angle <= tile_half_angle[i] + gamma) lists[i - first].push_back(&p);
      }
    }
    return lists;
  }

  // The ray o + t d against one solid primitive (decals lie on the ground: none here).
  static void Intersect(const Prim& p, const Eigen::Vector3d& o, const Eigen::Vector3d& d, Hit* hit) {
    switch (p.kind) {
      case PrimKind::kCone:
        IntersectCone(p, o, d, hit);
        break;
      case PrimKind::kBox:
        IntersectBox(p, o, d, hit);
        break;
      case PrimKind::kCylinder:
        IntersectCylinder(p, o, d, hit);
        break;
      case PrimKind::kDecal:
        break;
    }
  }

  // Casts one pixel's ray: the single code path behind Render and TracePixel.
  Hit Trace(const TruePose& pose, const Eigen::Vector3d& d, const std::vector<const Prim*>& list,
            const Prim** decal) const {
    const Eigen::Vector3d& o = pose.p_camera_in_cones_m;
    Hit hit;
    if (d.z() < 0.0) hit.t = -o.z() / d.z();  // ground plane z = 0
    *decal = nullptr;
    for (const Prim* p : list) Intersect(*p, o, d, &hit);
    if (hit.prim == nullptr && d.z() < 0.0) {
      const Eigen::Vector3d g = o + hit.t * d;
      for (const Prim* p : list)  // later decals (patches) paint over earlier ones (base plates)
        if (p->kind == PrimKind::kDecal && OnDecal(*p, g.x(), g.y())) *decal = p;
    }
    return hit;
  }

  // Whether the sun reaches point q (cones frame) along light.sun_dir: no caster of `casters` other
  // than `self` is in the way. Convex casters cannot shadow their own lit side.
  float SunVisible(const Eigen::Vector3d& q, const Prim* self, const std::vector<const Prim*>& casters,
                   const Lighting& light) const {
    const Eigen::Vector3d& l = light.sun_dir;
    for (const Prim* p : casters) {
      if (p == self) continue;
      const Eigen::Vector3d v = p->sphere_center - q;
      const double along = v.dot(l);
      if (along < -p->sphere_radius || v.squaredNorm() - along * along > p->sphere_radius * p->sphere_radius) continue;
      Hit h;
      Intersect(*p, q, l, &h);
      if (h.prim) return 0.0f;
    }
    return 1.0f;
  }

  // Any pixel: trace against the tile's objects, then shade.
  Eigen::Vector3f ShadePixel(const TruePose& pose, const Lighting& light, const std::vector<const Prim*>& list,
                             size_t i, const std::vector<const Prim*>* casters, int16_t* label) const {
    const Eigen::Vector3d d = pose.R_cones_camera * rays[i];
    const Prim* decal = nullptr;
    const Hit hit = Trace(pose, d, list, &decal);
    const Eigen::Vector3d& o = pose.p_camera_in_cones_m;
    *label = kLabelGround;
    if (!materials.look()) {
      if (hit.prim == nullptr && decal == nullptr && d.z() < 0.0)
        return materials.ShadeGround(o.x() + hit.t * d.x(), o.y() + hit.t * d.y(), hit.t / inv_norms[i], light);
      return materials.Shade(o, d, inv_norms[i], hit, decal, light, label);
    }
    float sun_visible = 1.0f;
    if (casters && (hit.prim != nullptr || d.z() < 0.0) && (hit.prim == nullptr || hit.normal.dot(light.sun_dir) > 0.0))
      sun_visible = SunVisible(o + hit.t * d, hit.prim, *casters, light);
    if (hit.prim == nullptr && decal == nullptr && d.z() < 0.0)
      return materials.ShadeGroundLook(o.x() + hit.t * d.x(), o.y() + hit.t * d.y(), hit.t / inv_norms[i], light,
                                       sun_visible);
    return materials.Shade(o, d, inv_norms[i], hit, decal, light, label, sun_visible);
  }

  // One pose of an exposure: the pose and its tiles' object lists.
  struct Pass {
    TruePose pose;
    std::vector<std::vector<const Prim*>> lists;
    // Single precision is plenty for bare ground (2 cm texels) and roughly halves its cost.
    Eigen::Matrix3f R;
    Eigen::Vector3f o;
  };

  // Linear radiance of pixel i (in tile `tile`) seen from one pass.
  Eigen::Vector3f PixelRadiance(const Pass& pass, const Lighting& light, const std::vector<const Prim*>* casters,
                                int tile, size_t i, int16_t* label) const {
    const std::vector<const Prim*>& list = pass.lists[tile];
    const Eigen::Matrix3f& R = pass.R;
    const Eigen::Vector3f& o = pass.o;
    *label = kLabelGround;
    const Eigen::Vector3f& r = rays_f[i];
    const float dz = R(2, 0) * r.x() + R(2, 1) * r.y() + R(2, 2) * r.z();
    if (list.empty() && dz < 0.0f) {  // no object near this tile's rays: bare ground
      const float t = -o.z() / dz;
      const float x = o.x() + t * (R(0, 0) * r.x() + R(0, 1) * r.y() + R(0, 2) * r.z());
      const float y = o.y() + t * (R(1, 0) * r.x() + R(1, 1) * r.y() + R(1, 2) * r.z());
      if (!materials.look()) return materials.ShadeGround(x, y, t * norms_f[i], light);
      const float sun_visible = casters ? SunVisible(Eigen::Vector3d(x, y, 0.0), nullptr, *casters, light) : 1.0f;
      return materials.ShadeGroundLook(x, y, t * norms_f[i], light, sun_visible);
    }
    if (list.empty()) {  // and no object: sky
      *label = kLabelSky;
      return materials.ShadeSky(dz / norms_f[i], light);
    }
    return ShadePixel(pass.pose, light, list, i, casters, label);
  }

  void RenderTileRow(const std::vector<Pass>& passes, const Lighting& light, const std::vector<const Prim*>* casters,
                     const Eigen::Vector3f& gain, int ty, uint32_t noise_offset, uint8_t* rgb, int16_t* labels) const {
    const bool add_noise = config.noise_sigma_dn > 0.0;
    const float exposure = static_cast<float>(config.exposure);
    const bool look = materials.look();
    const size_t n = passes.size(), mid = n / 2;
    const float inv_n = 1.0f / static_cast<float>(n);
    std::vector<float> row_radiance(3 * static_cast<size_t>(width));
    std::vector<int16_t> row_scratch(3 * static_cast<size_t>(width));
    for (int v = ty * kTile; v < std::min(height, (ty + 1) * kTile); ++v) {
      const int8_t* row_noise = &noise[(noise_offset + 3u * static_cast<uint32_t>(v) * width) & kNoiseMask];
      for (int tx = 0; tx < tiles_x; ++tx) {
        const int tile = ty * tiles_x + tx;
        if (!look && n == 1) {  // the plain look renders most frames: the tight loop, without the look's branches
          const std::vector<const Prim*>& list = passes[0].lists[tile];
          const Eigen::Matrix3f& R = passes[0].R;
          const Eigen::Vector3f& o = passes[0].o;
          for (int u = tx * kTile; u < std::min(width, (tx + 1) * kTile); ++u) {
            const size_t i = static_cast<size_t>(v) * width + u;
            int16_t label = kLabelGround;
            Eigen::Vector3f radiance;
            const Eigen::Vector3f& r = rays_f[i];
            const float dz = R(2, 0) * r.x() + R(2, 1) * r.y() + R(2, 2) * r.z();
            if (list.empty() && dz < 0.0f) {  // no object near this tile's rays: bare ground
              const float t = -o.z() / dz;
              const float x = o.x() + t * (R(0, 0) * r.x() + R(0, 1) * r.y() + R(0, 2) * r.z());
              const float y = o.y() + t * (R(1, 0) * r.x() + R(1, 1) * r.y() + R(1, 2) * r.z());
              radiance = materials.ShadeGround(x, y, t * norms_f[i], light);
            } else if (list.empty()) {  // and no object: sky
              radiance = materials.ShadeSky(dz / norms_f[i], light);
              label = kLabelSky;
            } else {
              radiance = ShadePixel(passes[0].pose, light, list, i, nullptr, &label);
            }
            row_radiance[3 * u] = radiance[0] * exposure;
            row_radiance[3 * u + 1] = radiance[1] * exposure;
            row_radiance[3 * u + 2] = radiance[2] * exposure;
            if (labels) labels[i] = label;
          }
          continue;
        }
        for (int u = tx * kTile; u < std::min(width, (tx + 1) * kTile); ++u) {
          const size_t i = static_cast<size_t>(v) * width + u;
          int16_t label = kLabelGround;
          Eigen::Vector3f radiance = PixelRadiance(passes[mid], light, casters, tile, i, &label);
          if (n > 1) {  // motion blur: the mean over the exposure
            int16_t other;
            for (size_t k = 0; k < n; ++k)
              if (k != mid) radiance += PixelRadiance(passes[k], light, casters, tile, i, &other);
            radiance *= inv_n;
          }
          if (look) {
            const float g = vignette.empty() ? 1.0f : vignette[i];
            row_radiance[3 * u] = radiance[0] * gain[0] * g;
            row_radiance[3 * u + 1] = radiance[1] * gain[1] * g;
            row_radiance[3 * u + 2] = radiance[2] * gain[2] * g;
          } else {
            row_radiance[3 * u] = radiance[0] * exposure;
            row_radiance[3 * u + 1] = radiance[1] * exposure;
            row_radiance[3 * u + 2] = radiance[2] * exposure;
          }
          if (labels) labels[i] = label;
        }
      }
      materials.EncodeRow(row_radiance.data(), add_noise ? row_noise : nullptr, 3 * width, row_scratch.data(),
                          rgb + 3 * static_cast<size_t>(v) * width, static_cast<float>(config.appearance.shot_noise));
    }
  }

  // The camera's gain per channel at time t: exposure, white balance and their drifts.
  Eigen::Vector3f Gain(double t) const {
    const AppearanceConfig& a = config.appearance;
    const double w = 2.0 * kPi / a.drift_period_s;
    const double phase =
        2.0 * kPi * static_cast<double>(SplitMix64(config.seed ^ 0x7762ull) >> 11) / 9007199254740992.0;
    const double exposure = config.exposure * (1.0 + a.exposure_drift * std::sin(w * t + phase));
    const double wb = a.white_balance_drift * std::sin(0.61 * w * t + 2.0 * phase);
    const Eigen::Vector3d g(a.white_balance_gain.x() * (1.0 + wb), a.white_balance_gain.y(),
                            a.white_balance_gain.z() * (1.0 - wb));
    return (exposure * g).cast<float>();
  }
};

Renderer::Renderer(const rig_model::CameraModel& camera, const Scene& scene, const RenderConfig& config)
    : impl_(new Impl(camera, scene, config)) {}
Renderer::~Renderer() = default;
int Renderer::width() const { return impl_->width; }
int Renderer::height() const { return impl_->height; }

void Renderer::Render(const TruePose& pose, double t_s, uint64_t frame_index, uint8_t* rgb, int16_t* labels) const {
  RenderExposure({pose}, t_s, frame_index, rgb, labels);
}

void Renderer::RenderExposure(const std::vector<TruePose>& poses, double t_s, uint64_t frame_index, uint8_t* rgb,
                              int16_t* labels) const {
  const Impl& m = *impl_;
  if (poses.empty()) throw std::invalid_argument("Renderer::RenderExposure: no pose");
  std::vector<Impl::Pass> passes(poses.size());
  for (size_t k = 0; k < poses.size(); ++k) {
    passes[k].pose = poses[k];
    passes[k].lists = m.CullTiles(poses[k], 0, m.tiles_x * m.tiles_y);
    passes[k].R = poses[k].R_cones_camera.cast<float>();
    passes[k].o = poses[k].p_camera_in_cones_m.cast<float>();
  }
  const Lighting light = m.materials.LightingAt(t_s);
  // Shadow casters: every solid object, when the sun is up.
  std::vector<const Prim*> casters;
  const bool shadows = m.config.appearance.shadows && light.sun_dir.z() > 0.0 && light.sun > 0.0f;
  if (shadows)
    for (const Prim& p : m.prims)
      if (p.kind != PrimKind::kDecal) casters.push_back(&p);
  const Eigen::Vector3f gain = m.Gain(t_s);
  const uint32_t noise_offset = static_cast<uint32_t>(SplitMix64(m.config.seed * 0x100000001B3ull + frame_index));
  std::atomic<int> next_row{0};
  auto work = [&]() {
    for (int ty = next_row++; ty < m.tiles_y; ty = next_row++)
      m.RenderTileRow(passes, light, shadows ? &casters : nullptr, gain, ty, noise_offset, rgb, labels);
  };
  const int n = std::max(1, m.config.threads);
  std::vector<std::thread> pool;
  for (int k = 1; k < n; ++k) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
}

RayHit Renderer::TracePixel(const TruePose& pose, int u, int v) const {
  const Impl& m = *impl_;
  RayHit out;
  if (u < 0 || v < 0 || u >= m.width || v >= m.height) return out;
  const int tile = (v / kTile) * m.tiles_x + u / kTile;
  const auto lists = m.CullTiles(pose, tile, tile + 1);  // only the pixel's tile, the same list Render uses
  const Eigen::Vector3d d = pose.R_cones_camera * m.rays[static_cast<size_t>(v) * m.width + u];
  const Prim* decal = nullptr;  // the same Trace as ShadePixel
  const Hit hit = m.Trace(pose, d, lists[0], &decal);
  if (hit.prim)
    out.label = hit.prim->label;
  else if (d.z() < 0.0)
    out.label = decal && decal->label != 0 ? decal->label : kLabelGround;
  else
    return out;
  out.t = hit.t;
  out.p_in_cones_m = pose.p_camera_in_cones_m + hit.t * d;
  return out;
}

}  // namespace rig_sim
