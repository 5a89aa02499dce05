// A CPU ray caster for the rig's camera.
//
// Why not OpenGL: every object in the scene is analytic (cones, boxes,
// cylinders, the ground plane), so casting one ray per pixel gives the exact
// silhouettes, and the per-pixel ray table (built once from rig_model::CameraModel's
// Newton undistortion, 3.11) applies the lens distortion exactly instead of
// through a resampled warp of a pinhole render. Screen tiles are culled
// against each object's bounding sphere, so a 1024x768 frame costs a few ms
// per core. Deterministic: the image noise comes from a table indexed by a
// hash of (seed, frame index), independent of the thread count.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rig_sim/camera_model.h"
#include "rig_sim/scene.h"
#include "rig_sim/trajectory.h"

namespace rig_sim {

struct LightingConfig {
  double sun_elevation_deg = 50.0;
  double sun_azimuth_deg = 30.0;
  double sun_irradiance = 0.85;  // relative; 1 is a bright clear day
  double ambient = 0.30;         // sky light
  double variation = 0.2;        // relative swing of the sun (passing clouds)
  double variation_period_s = 17.0;
  double azimuth_drift_deg_s = 0.5;
};

// How the world and the camera look beyond the geometry: cast shadows, coloured light, weathered
// cones and the camera's white balance, exposure, noise and motion blur (issue 15.4). Looks
// (scenario.h, ApplyLook) are named presets of these. Every default leaves a frame byte-identical
// to a renderer without them.
struct AppearanceConfig {
  // Light.
  bool shadows = false;                                  // cones, boxes and people shadow the ground and each other
  Eigen::Vector3d sun_colour = Eigen::Vector3d::Ones();  // linear RGB of the direct sun (warm at a low sun)
  Eigen::Vector3d sky_colour = Eigen::Vector3d::Ones();  // linear RGB of the sky light (bluish shadows)
  // Cones: 0 new .. 1 very dirty. Each cone gets between 40 % and 100 % of it (drawn from the
  // seed): darker, less saturated, hue toward brown, dirt mottled at ~3 cm and heavier near the base,
  // the white collars greyed.
  double cone_weathering = 0.0;
  // Camera.
  Eigen::Vector3d white_balance_gain = Eigen::Vector3d::Ones();  // per-channel gain on linear RGB
  double white_balance_drift = 0.0;  // relative swing of the red and blue gains (auto white balance hunting)
  double exposure_drift = 0.0;       // relative swing of the exposure (auto exposure hunting), < 1
  double drift_period_s = 13.0;      // of both swings
  double shot_noise = 0.0;  // noise grows with the signal: sigma = noise_sigma_dn * sqrt(1 + shot_noise * DN / 255)
  double vignetting = 0.0;  // fraction of light lost in the image corners (cos^4-like falloff)
  double exposure_time_s = 0.0;  // shutter open time, centred on the frame stamp: motion blur when > 0
  int blur_samples = 1;          // poses averaged over the exposure (SimStream samples the trajectory)

  bool Active() const;  // anything differs from the defaults
  // "" when valid, else which field is out of range.
  std::string Validate() const;
};

struct RenderConfig {
  LightingConfig lighting;
  AppearanceConfig appearance;
  double exposure = 1.0;
  double noise_sigma_dn = 2.0;  // image noise, 8-bit digital numbers, 0 disables
  int threads = 2;
  uint64_t seed = 1;
  bool tile_culling = true;  // false tests every object on every pixel (the benchmark's naive baseline)
};

// Per-pixel label values written when a label buffer is given.
constexpr int16_t kLabelSky = -1;
constexpr int16_t kLabelGround = 0;
constexpr int16_t kLabelFirstCone = 1;  // cone i -> 1 + i
constexpr int16_t kLabelFirstDistractor = 1000;

struct RayHit {
  int16_t label = kLabelSky;
  double t = 0.0;  // along the ray, for the ray direction with z = 1
  Eigen::Vector3d p_in_cones_m = Eigen::Vector3d::Zero();
};

class Renderer {
 public:
  Renderer(const rig_model::CameraModel& camera, const Scene& scene, const RenderConfig& config);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  int width() const;
  int height() const;
  // Renders the view from T_cones_camera at scenario time t_s (lighting varies
  // with time). rgb: width*height*3 bytes, rgb8 row-major. labels: optional,
  // width*height entries.
  void Render(const TruePose& T_cones_camera, double t_s, uint64_t frame_index, uint8_t* rgb,
              int16_t* labels = nullptr) const;
  // The same with motion blur: the linear radiance averaged over the poses the camera passes through
  // while the shutter is open (in time order). Labels are those of the middle pose.
  void RenderExposure(const std::vector<TruePose>& poses_during_exposure, double t_s, uint64_t frame_index,
                      uint8_t* rgb, int16_t* labels = nullptr) const;
  // What the renderer's ray for pixel (u, v) hits: the same code path as Render.
  RayHit TracePixel(const TruePose& T_cones_camera, int u, int v) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rig_sim
