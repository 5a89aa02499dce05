// Outages on a walk through a large layout (rig_sim's `site_look_away`): the walker looks down at the
// ground ahead of the feet, where no cone is in view, for a few seconds, then up at exactly two cones
// (the cones beyond them above the image), held for a while
// before the walk's own view (usually with more cones) returns. The re-acquisition after an outage on
// a large layout must work from those two cones. ROS-free.
#pragma once

#include <string>
#include <vector>

#include "rig_sim/scenario.h"

namespace rig_sim {

struct OutagePlanConfig {
  // The turn away begins (before ShortenScenario) here or up to start_window_s later (1 s steps, the
  // first that fits; and at least 5 s after the previous outage's end).
  std::vector<double> starts_s = {8.0, 34.0};
  double start_window_s = 16.0;
  double min_away_s = 3.0;  // the stretch looking down, drawn per seed in [min, max]
  double max_away_s = 6.0;
  double shift_max_s = 2.0;      // the return may move by up to this to find a two-cone view (away kept in 2-8 s)
  double ramp_s = 1.2;           // each turn
  double pair_hold_s = 2.5;      // two cones in view, nothing else
  double down_pitch_deg = 75.0;  // the outage's look below the horizon, at the ground ahead of the feet
  // In full-resolution pixels of the scenario's camera: the pair's cones stand at least this tall and
  // this far inside the image while held; any other cone touching the image (peak, mid or base within
  // other_margin_px of it) is at most other_max_px tall (the tracker's min_area_px 30 at 512x384 needs
  // a cone of about 15 px there, 30 px here; ar_bringup's `resolved` split counts cones of 30 px there).
  double pair_min_px = 60.0;
  double pair_margin_px = 40.0;
  double other_margin_px = 10.0;
  double other_max_px = 24.0;
  double max_rate_deg_s = 250.0;  // the turns stay below this (the Crista saturates at 300 deg/s)
  double min_range_m = 1.5;       // camera to a pair cone's base
  double max_range_m = 10.0;
};

// What was planned per outage (for make_bag's report and the tests).
struct PlannedOutage {
  double away_start_s = 0.0;     // last cone leaves the view around here + ramp / 2
  double away_s = 0.0;           // down, no cone: from away_start_s + ramp_s to pair_turn_s
  double pair_turn_s = 0.0;      // the turn up to the pair begins
  double pair_end_s = 0.0;       // the pair's hold ends; the walk's view returns over ramp_s
  int cone_a = -1, cone_b = -1;  // layout indices of the pair
};

// Replaces the scenario's look-at segments by the planned outages (one kLookAt segment each).
// Needs the scene, the full-size camera and the seeded walk (s->trajectory.seed). Returns false with a
// message naming the outage's time and the layout's cone count when no two-cone view is found.
bool PlanOutages(const OutagePlanConfig& config, Scenario* s, std::vector<PlannedOutage>* planned, std::string* error);

}  // namespace rig_sim
