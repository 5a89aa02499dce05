#include "rig_sim/scenario.h"

#include "rig_sim/outage_plan.h"

#include <algorithm>
#include <cmath>

namespace rig_sim {
namespace {

Segment Still(double start_s, double duration_s) { return {SegmentKind::kStill, start_s, duration_s, 0.5, 0.0, 0.0}; }
Segment Shake(double start_s, double duration_s, double amplitude_deg, double frequency_hz) {
  return {SegmentKind::kShake, start_s, duration_s, 0.4, amplitude_deg, frequency_hz};
}
Segment LookAway(double start_s, double duration_s, double pan_deg) {
  return {SegmentKind::kLookAway, start_s, duration_s, 1.2, pan_deg, 0.0};
}

}  // namespace

const std::vector<ScenarioInfo>& ListScenarios() {
  static const std::vector<ScenarioInfo> list = {
      {"handheld",
       "60 s walk around the default three road cones at 1.5-4 m: still start (3 s), shakes, "
       "a 4 s stretch with the cones out of view, another still"},
      {"still", "10 s with the rig at rest (gyro bias and gravity calibration)"},
      {"shake", "20 s with fast shakes up to ~200 deg/s"},
      {"look_away", "20 s with a 6 s stretch panned away from the cones (the gyro experiment, 7.3)"},
      {"clutter",
       "30 s around an asymmetric four-cone layout on grass among orange boxes, patches and a "
       "person in hi-vis, with stronger lighting changes"},
      {"stacked", "20 s around stacked cones on concrete"},
      {"indoor", "20 s around the thesis's three 4\" plain cones at 0.5-1.2 m, indoors"},
      {"realistic",
       "the handheld walk (60 s) around three mixed road cones (one wide European sleeve, two US "
       "two-band collars) in the realistic look: sun and cloud with cast shadows, weathered cones, "
       "white balance and exposure hunting, shot noise, vignetting, motion blur"},
      {"survey",
       "40 s walk-around of a layout for cone_survey's survey_layout (any layout with --layout; default "
       "survey.yaml, seven mixed cones): a still start (2 s), then one loop on a circle 2.2 m outside the "
       "cones at 1.2-1.8 m height, looking at points swept across the layout"},
      {"site",
       "60 s walk through a site of 14 cones over about 19 m x 19 m (site.yaml): one loop between an inner "
       "ring and an outer ring, 1.5-6 m from the nearest cones, looking across the site, often with only "
       "one or two cones in view"},
      {"site_look_away",
       "the site walk (60 s, site.yaml or --layout) with two outages: the walker looks down at the ground "
       "ahead for 2-8 s (no cone in view), then at exactly two cones for 2.5 s before the walk's view returns"},
  };
  return list;
}

const std::vector<ScenarioInfo>& ListLooks() {
  static const std::vector<ScenarioInfo> list = {
      {"plain", "clean cones, no cast shadows, a steady camera (what rig_sim always rendered)"},
      {"sunny", "a clear day: cast shadows, bluish sky light, a bright sun at 45 deg"},
      {"overcast", "thick cloud: almost no direct sun, flat bright sky light, faint shadows"},
      {"low_sun", "evening sun at 10 deg: warm light, long cast shadows, blue shade"},
      {"weathered", "faded, dirty, mottled cones with grey collars (lighting as the scenario's)"},
      {"camera",
       "the camera's faults only: white balance and exposure hunting, shot noise, vignetting, "
       "6 ms motion blur"},
      {"realistic", "all of it: sun and passing cloud with cast shadows, weathered cones, the camera's faults"},
  };
  return list;
}

bool ApplyLook(const std::string& name, Scenario* s, std::string* error) {
  const bool known =
      std::any_of(ListLooks().begin(), ListLooks().end(), [&](const ScenarioInfo& i) { return i.name == name; });
  if (known) s->render = s->base_render;
  LightingConfig& l = s->render.lighting;
  AppearanceConfig& a = s->render.appearance;
  auto sunny = [&](double elevation_deg) {
    a.shadows = true;
    l.sun_elevation_deg = elevation_deg;
    l.sun_irradiance = 1.0;
    l.ambient = 0.25;
    a.sun_colour = Eigen::Vector3d(1.0, 0.96, 0.88);
    a.sky_colour = Eigen::Vector3d(0.80, 0.92, 1.20);
  };
  auto weathered = [&](double amount) { a.cone_weathering = amount; };
  auto camera = [&]() {
    a.white_balance_gain = Eigen::Vector3d(1.06, 1.0, 0.92);
    a.white_balance_drift = 0.08;
    a.exposure_drift = 0.3;
    a.shot_noise = 4.0;
    s->render.noise_sigma_dn = 2.5;
    a.vignetting = 0.3;
    a.exposure_time_s = 0.006;
    a.blur_samples = 5;
  };
  if (name == "plain") {
  } else if (name == "sunny") {
    sunny(45.0);
  } else if (name == "overcast") {
    a.shadows = true;
    l.sun_irradiance = 0.08;
    l.ambient = 0.75;
    l.variation = 0.05;
    a.sky_colour = Eigen::Vector3d(0.95, 0.98, 1.05);
  } else if (name == "low_sun") {
    sunny(10.0);
    l.sun_irradiance = 1.1;
    l.ambient = 0.18;
    a.sun_colour = Eigen::Vector3d(1.0, 0.68, 0.38);
    a.sky_colour = Eigen::Vector3d(0.65, 0.82, 1.30);
  } else if (name == "weathered") {
    weathered(0.8);
  } else if (name == "camera") {
    camera();
  } else if (name == "realistic") {
    sunny(32.0);
    l.sun_irradiance = 0.85;
    l.variation = 0.7;  // passing cloud: the sun between ~0.3 and ~1.7 of its mean
    l.variation_period_s = 21.0;
    weathered(0.6);
    camera();
  } else {
    std::string names;
    for (const auto& i : ListLooks()) names += " " + i.name;
    if (error) *error = "unknown look '" + name + "'; known:" + names;
    return false;
  }
  s->look = name;
  return true;
}

bool MakeScenario(const std::string& name, uint64_t seed, const std::string& layouts_dir, Scenario* out,
                  std::string* error) {
  Scenario s;
  s.name = name;
  s.layout = "default.yaml";
  TrajectoryConfig& t = s.trajectory;
  if (name == "handheld") {
    t.duration_s = 60.0;
    t.segments = {Still(-1.0, 4.5), Shake(14.0, 3.0, 7.0, 3.0), LookAway(24.0, 6.4, 100.0), Still(38.0, 4.0),
                  Shake(48.0, 2.5, 6.0, 4.0)};
  } else if (name == "still") {
    t.duration_s = 10.0;
    t.segments = {Still(-1.0, 12.0)};
  } else if (name == "shake") {
    t.duration_s = 20.0;
    t.segments = {Still(-1.0, 3.0), Shake(3.0, 5.0, 6.5, 3.5), Shake(11.0, 6.0, 5.0, 5.0)};
  } else if (name == "look_away") {
    t.duration_s = 20.0;
    t.segments = {Still(-1.0, 3.0), LookAway(5.0, 8.4, 110.0)};
  } else if (name == "clutter") {
    t.duration_s = 30.0;
    s.layout = "clutter.yaml";
    t.segments = {Still(-1.0, 3.0), Shake(18.0, 2.0, 6.0, 3.0)};
    t.orbit_rate_deg_s = 12.0;
    s.render.lighting.variation = 0.4;
    s.render.lighting.variation_period_s = 9.0;
  } else if (name == "stacked") {
    t.duration_s = 20.0;
    s.layout = "stacked.yaml";
    t.segments = {Still(-1.0, 3.0)};
  } else if (name == "realistic") {
    t.duration_s = 60.0;
    s.layout = "realistic.yaml";
    t.segments = {Still(-1.0, 4.5), Shake(14.0, 3.0, 7.0, 3.0), LookAway(24.0, 6.4, 100.0), Still(38.0, 4.0),
                  Shake(48.0, 2.5, 6.0, 4.0)};
  } else if (name == "survey") {
    t.duration_s = 40.0;
    s.layout = "survey.yaml";
    t.segments = {Still(-1.0, 3.0)};
    t.look_target_height_m = 0.2;
  } else if (name == "site" || name == "site_look_away") {
    t.duration_s = 60.0;
    s.layout = "site.yaml";
    t.segments = {Still(-1.0, 3.0)};
    t.survey_radius_m = 6.0;  // between the rings (3 m and ~9 m)
    t.survey_loops = 1.0;
    t.survey_sweep_m = 5.0;  // the look swings far across the site
    t.min_distance_m = 5.0;  // 6 m +- 8 %, 1.2-1.8 m high, from the look target
    t.max_distance_m = 7.0;
    if (name == "site_look_away") t.survey_loop_s = t.duration_s;  // cut short, the same walk and outages
  } else if (name == "indoor") {
    t.duration_s = 20.0;
    s.layout = "thesis_indoor.yaml";
    t.min_distance_m = 0.5;
    t.max_distance_m = 1.2;
    t.look_target_height_m = 0.05;
    t.segments = {Still(-1.0, 3.0)};
    s.render.lighting.sun_irradiance = 0.3;  // indoor light: mostly diffuse
    s.render.lighting.ambient = 0.6;
    s.render.lighting.variation = 0.05;
  } else {
    std::string names;
    for (const auto& i : ListScenarios()) names += " " + i.name;
    if (error) *error = "unknown scenario '" + name + "'; known:" + names;
    return false;
  }
  for (const auto& i : ListScenarios())
    if (i.name == name) s.description = i.description;
  if (!LoadSceneYaml(layouts_dir + "/" + s.layout, &s.scene, error)) return false;
  // Independent streams per component, all from the one seed.
  t.seed = seed;
  s.imu.seed = seed * 0x9E3779B97F4A7C15ull + 1;
  s.render.seed = seed * 0xC2B2AE3D27D4EB4Full + 2;
  if (!FitTrajectoryToScene(&s, error)) return false;
  s.base_render = s.render;
  if (name == "realistic" && !ApplyLook("realistic", &s, error)) return false;
  *out = s;
  return true;
}

bool FitTrajectoryToScene(Scenario* s, std::string* error) {
  if (s->name == "site_look_away") return PlanOutages(OutagePlanConfig(), s, nullptr, error);
  if (s->name != "survey" || s->scene.cones.empty()) return true;
  Eigen::Vector2d lo = s->scene.cones[0].base_m.head<2>(), hi = lo;
  for (const ConeSpec& c : s->scene.cones) {
    lo = lo.cwiseMin(c.base_m.head<2>());
    hi = hi.cwiseMax(c.base_m.head<2>());
  }
  const Eigen::Vector2d centre = 0.5 * (lo + hi);
  double reach_m = 0.0;  // the hull's farthest point from the centre
  for (const ConeSpec& c : s->scene.cones) reach_m = std::max(reach_m, (c.base_m.head<2>() - centre).norm());
  TrajectoryConfig& t = s->trajectory;
  t.survey_center_m = centre;
  t.survey_radius_m = reach_m + 2.2;
  t.survey_sweep_m = std::min(1.5, 0.6 * reach_m);
  // The walk's range of distances from the origin's look target (radius within +-8 %, 1.2-1.8 m high).
  const double off_m = centre.norm(), rise_m = 1.8 - t.look_target_height_m;
  t.min_distance_m = std::max(0.3, 0.92 * t.survey_radius_m - off_m);
  t.max_distance_m = std::hypot(1.08 * t.survey_radius_m + off_m, rise_m);
  return true;
}

void ShortenScenario(double duration_s, double image_scale, Scenario* s) {
  if (duration_s > 0.0) s->trajectory.duration_s = std::min(s->trajectory.duration_s, duration_s);
  if (image_scale > 0.0 && image_scale != 1.0) s->camera = s->camera.Scaled(image_scale);
}

}  // namespace rig_sim
