// Correspondence without a prediction for large layouts (3.1.6 scaled to up to
// 30 cones with a few in view): no enumeration of all assignments. Each
// detection's cone axis gives, with the world's up direction in the camera
// (the axes' common vanishing direction), its base point in the camera frame
// up to the cone's height (the depth scales with the height). A pair of
// detections hypothesised as a pair of layout cones must then have the
// layout's spacing; the survivors give a rough pose each (up and the pair's
// horizontal direction), which projects the cones whose spacing to both of the
// pair's fits some other detection and matches those detections. The best few
// assignments go to the full solver, each with its rough pose as the start.
// Work per frame: O(D^2 N^2) distance checks for D detections (the largest
// max_detections) and N cones, plus a projection per fitting (detection, cone)
// of each surviving hypothesis. ROS-free.
#pragma once

#include <cstddef>
#include <vector>

#include "cone_tracker/vision/cone_pose.h"

namespace cone_tracker {

struct ConeSearchConfig {
  size_t max_detections = 12;            // hypotheses from the largest this many detections
  size_t max_hypotheses = 4000;          // pair hypotheses scored per frame, at most
  size_t max_candidates = 6;             // assignments handed to the solver
  size_t max_rivals = 12;                // assignments returned: beyond max_candidates checked as rivals only
  double spacing_tol_frac = 0.2;         // a pair fits when its spacing matches within this fraction ...
  double spacing_tol_m = 0.15;           // ... plus this
  double match_gate_height_frac = 0.35;  // a detection matches a projected cone within this fraction of its height
  double match_gate_min_rad = 0.03;      // ... or within this angle (far cones: the rough pose's angular error)
  double max_axis_off_rad = 0.03;        // an axis this far off the common vertical is left out of it (a distractor)
  // A solved candidate with a larger reprojection RMS (px) ranks below every consistent one.
  double max_consistent_rms_px = 3.0;
};

// A candidate assignment (model cone per detection, -1 none) and the rough pose
// that matched it: a start for the solver near the assignment's own optimum.
struct SearchCandidate {
  std::vector<int> assignment;
  pose_math::Pose rough_T_camera_cones;
};

// Candidates with at least three matches each, best first (most matches, then
// the lowest rough residual).
std::vector<SearchCandidate> SearchAssignments(const std::vector<ConeDetection>& detections,
                                               const std::vector<ConeModel>& cones, const CameraModel& camera,
                                               const ConeSearchConfig& config);

}  // namespace cone_tracker
