// Smooth handheld camera trajectories around the cones, with still segments,
// fast shakes and stretches where the cones leave the view (7.3). The pose is
// an analytic, infinitely differentiable function of time (built from
// sinusoids and C2 smooth steps), deterministic given the seed. ROS-free.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace rig_sim {

enum class SegmentKind { kStill, kShake, kLookAway, kLookAt };

// A look of a kLookAt segment: from start_s (seconds into the segment) the camera turns, over the
// segment's ramp_s, to look at target_m (in `cones`, horizon level) from wherever the walk has it;
// with `relative`, target_m is an offset from the camera (e.g. down at the ground ahead of the feet).
struct LookKey {
  double start_s = 0.0;
  Eigen::Vector3d target_m = Eigen::Vector3d::Zero();
  bool relative = false;
};

struct Segment {
  SegmentKind kind = SegmentKind::kStill;
  double start_s = 0.0;
  double duration_s = 2.0;     // including both ramps
  double ramp_s = 0.5;         // C2 smooth step in and out
  double amplitude_deg = 0.0;  // shake: per-axis amplitude; look-away: pan angle
  double frequency_hz = 0.0;   // shake only
  // kLookAt only: the looks in order, each turned to over ramp_s from the previous one (the first
  // from the walk's own view); the last is held until duration_s - ramp_s, then the camera turns
  // back to the walk's view. The walk's position goes on meanwhile.
  std::vector<LookKey> looks = {};
};

struct TrajectoryConfig {
  double duration_s = 60.0;
  uint64_t seed = 1;
  double min_distance_m = 1.5;  // camera to the look target
  double max_distance_m = 4.0;
  double min_elevation_deg = 15.0;  // of the camera above the look target
  double max_elevation_deg = 40.0;
  double orbit_rate_deg_s = 8.0;  // mean walk around the cones
  double look_target_height_m = 0.3;
  double jitter_deg = 1.5;        // hand tremor amplitude
  std::vector<Segment> segments;  // must not overlap
  // Survey walk (rig_sim's `survey` scenario, for cone_survey's survey_layout): when
  // survey_radius_m > 0 the camera walks survey_loops times around a circle of that radius about
  // survey_center_m at 1.2-1.8 m height, looking at ground points swept across the layout, instead
  // of the orbit above. The loop rate follows from the duration (a shortened walk still closes it).
  double survey_radius_m = 0.0;
  double survey_loops = 1.15;
  Eigen::Vector2d survey_center_m = Eigen::Vector2d::Zero();
  double survey_sweep_m = 1.0;  // half-width of the look target's sweep across the layout
  // The loops take this long (0: the duration, so a shortened walk still closes them); > 0 makes a
  // shortened walk the first part of the full one (site_look_away: its outages are planned on that).
  double survey_loop_s = 0.0;
  std::string Validate() const;
};

struct TruePose {
  Eigen::Matrix3d R_cones_camera;  // p_cones = R p_camera + t
  Eigen::Vector3d p_camera_in_cones_m;
};

class Trajectory {
 public:
  // Throws std::invalid_argument with Validate()'s message on a bad config.
  explicit Trajectory(const TrajectoryConfig& config);
  const TrajectoryConfig& config() const { return config_; }

  TruePose At(double t_s) const;
  // Angular velocity of camera_optical in its own frame (central difference of
  // the analytic pose; used for checks and ground truth twist).
  Eigen::Vector3d OmegaCamera(double t_s) const;
  // True while a still segment holds the rig fully at rest (ramps excluded).
  bool IsStill(double t_s) const;

 private:
  double Warp(double t_s) const;  // motion time s(t): stops in still segments
  double Window(const Segment& seg, double t_s) const;
  TruePose BaseAt(double s) const;
  TruePose SurveyAt(double s) const;
  Eigen::Matrix3d LookAtSegment(const Segment& seg, double t_s, const TruePose& walk) const;

  TrajectoryConfig config_;
  // Seeded sinusoid parameters: frequencies (Hz) and phases (rad).
  double phase_[12];
  double freq_[12];
  Eigen::Vector3d shake_phase_;
  double survey_rate_rad_s_ = 0.0;  // loop rate in motion time s
};

// C2 smooth step 6x^5 - 15x^4 + 10x^3 on [0, 1], clamped outside.
double SmoothStep(double x);

}  // namespace rig_sim
