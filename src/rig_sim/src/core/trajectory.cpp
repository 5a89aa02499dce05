#include "rig_sim/trajectory.h"

#include "angles.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include <Eigen/Geometry>

namespace rig_sim {
namespace {

// Integral of SmoothStep from 0 to x, for x in [0, 1].
double SmoothStepIntegral(double x) { return x * x * x * x * (x * (x - 3.0) + 2.5); }

Eigen::Matrix3d ExpSo3(const Eigen::Vector3d& r) {
  const double a = r.norm();
  if (a < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(a, r / a).toRotationMatrix();
}

// Camera_optical looking from p at target: z forward, x right (horizontal), y down.
Eigen::Matrix3d LookAt(const Eigen::Vector3d& p, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - p).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  Eigen::Matrix3d R;
  R << x, z.cross(x), z;
  return R;
}

}  // namespace

double SmoothStep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * x * (x * (6.0 * x - 15.0) + 10.0);
}

std::string TrajectoryConfig::Validate() const {
  std::ostringstream err;
  if (!(duration_s > 0.0))
    err << "duration_s must be positive";
  else if (!(min_distance_m > 0.2 && max_distance_m >= min_distance_m))
    err << "need 0.2 < min_distance_m <= max_distance_m";
  else if (!(min_elevation_deg >= 0.0 && max_elevation_deg <= 85.0 && min_elevation_deg <= max_elevation_deg))
    err << "need 0 <= min_elevation_deg <= max_elevation_deg <= 85";
  else if (!(survey_radius_m >= 0.0 && survey_radius_m < 200.0 && survey_loops > 0.0 && survey_sweep_m >= 0.0 &&
             survey_loop_s >= 0.0))
    err << "need 0 <= survey_radius_m < 200, survey_loops > 0, survey_sweep_m >= 0 and survey_loop_s >= 0";
  if (!err.str().empty()) return err.str();
  std::vector<Segment> sorted = segments;
  std::sort(sorted.begin(), sorted.end(), [](const Segment& a, const Segment& b) { return a.start_s < b.start_s; });
  for (size_t i = 0; i < sorted.size(); ++i) {
    const Segment& s = sorted[i];
    if (!(s.ramp_s > 0.0) || !(s.duration_s >= 2.0 * s.ramp_s))
      return "segment at " + std::to_string(s.start_s) + " s: need ramp_s > 0 and duration_s >= 2 ramp_s";
    if (s.kind == SegmentKind::kLookAt) {
      if (s.looks.empty()) return "look-at segment at " + std::to_string(s.start_s) + " s: no looks";
      for (size_t k = 0; k < s.looks.size(); ++k) {
        const double next_s = k + 1 < s.looks.size() ? s.looks[k + 1].start_s : s.duration_s - s.ramp_s;
        if (!(s.looks[k].start_s >= 0.0 && s.looks[k].start_s + s.ramp_s <= next_s))
          return "look-at segment at " + std::to_string(s.start_s) + " s: looks[" + std::to_string(k) +
                 "] must start at >= 0 s and turn (ramp_s) before the next look or the turn back";
      }
    }
    if (i + 1 < sorted.size() && s.start_s + s.duration_s > sorted[i + 1].start_s)
      return "segments at " + std::to_string(s.start_s) + " s and " + std::to_string(sorted[i + 1].start_s) +
             " s overlap";
  }
  return "";
}

Trajectory::Trajectory(const TrajectoryConfig& config) : config_(config) {
  const std::string err = config.Validate();
  if (!err.empty()) throw std::invalid_argument("TrajectoryConfig: " + err);
  std::mt19937_64 rng(config.seed);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * kPi);
  // Slow components (walk, distance, height) below 0.1 Hz; tremor 0.4-1.5 Hz.
  const double lo[12] = {0.02, 0.03, 0.025, 0.04, 0.05, 0.03, 0.4, 0.5, 0.45, 0.9, 1.1, 1.3};
  for (int i = 0; i < 12; ++i) {
    phase_[i] = phase(rng);
    freq_[i] = lo[i] * std::uniform_real_distribution<double>(1.0, 1.6)(rng);
  }
  shake_phase_ = Eigen::Vector3d(phase(rng), phase(rng), phase(rng));
  // The loop closes over the walk's motion time (still segments stop it).
  const double loop_s = config.survey_loop_s > 0.0 ? config.survey_loop_s : config.duration_s;
  survey_rate_rad_s_ = 2.0 * kPi * config.survey_loops / std::max(1.0, Warp(loop_s));
}

double Trajectory::Window(const Segment& seg, double t) const {
  const double end = seg.start_s + seg.duration_s;
  if (t <= seg.start_s || t >= end) return 0.0;
  if (t < seg.start_s + seg.ramp_s) return SmoothStep((t - seg.start_s) / seg.ramp_s);
  if (t > end - seg.ramp_s) return 1.0 - SmoothStep((t - (end - seg.ramp_s)) / seg.ramp_s);
  return 1.0;
}

double Trajectory::Warp(double t) const {
  // s(t) = t - sum of the integrals of the still windows: ds/dt = 1 - W(t),
  // so every motion term (all functions of s) stops smoothly in a still segment.
  double s = t;
  for (const Segment& seg : config_.segments) {
    if (seg.kind != SegmentKind::kStill || t <= seg.start_s) continue;
    const double r = seg.ramp_s, hold = seg.duration_s - 2.0 * r;
    const double x = t - seg.start_s;
    double integral;
    if (x < r)
      integral = r * SmoothStepIntegral(x / r);
    else if (x < r + hold)
      integral = 0.5 * r + (x - r);
    else if (x < 2.0 * r + hold) {
      const double y = (x - r - hold) / r;
      integral = 0.5 * r + hold + r * (y - SmoothStepIntegral(y));
    } else
      integral = seg.duration_s - r;
    s -= integral;
  }
  return s;
}

bool Trajectory::IsStill(double t) const {
  for (const Segment& seg : config_.segments)
    if (seg.kind == SegmentKind::kStill && t >= seg.start_s + seg.ramp_s &&
        t <= seg.start_s + seg.duration_s - seg.ramp_s)
      return true;
  return false;
}

TruePose Trajectory::SurveyAt(double s) const {
  const TrajectoryConfig& c = config_;
  // Height, pitch and the sweep vary with the walk's azimuth (not with time), so a short walk
  // varies them as much as a long one and every cone is seen from several directions and heights.
  const double a = phase_[0] + survey_rate_rad_s_ * s;
  const Eigen::Vector2d radial(std::cos(a), std::sin(a)), tangent(-std::sin(a), std::cos(a));
  const double height_m = 1.5 + 0.3 * std::sin(2.0 * a + phase_[1]);
  const double radius_m = c.survey_radius_m * (1.0 + 0.08 * std::sin(2.0 * a + phase_[2]));
  const Eigen::Vector2d p_xy = c.survey_center_m + radius_m * radial;
  const Eigen::Vector2d target_xy = c.survey_center_m + c.survey_sweep_m * std::sin(3.0 * a + phase_[3]) * tangent +
                                    0.5 * c.survey_sweep_m * std::sin(2.0 * a + phase_[4]) * radial;
  const Eigen::Vector3d p(p_xy.x(), p_xy.y(), height_m);
  const Eigen::Vector3d target(target_xy.x(), target_xy.y(), c.look_target_height_m);
  const Eigen::Matrix3d R = LookAt(p, target);
  auto wave = [&](int i) { return std::sin(2.0 * kPi * freq_[i] * s + phase_[i]); };
  const double j = c.jitter_deg * kDeg;
  const Eigen::Vector3d tremor_rad(j * wave(9), j * wave(10), 4.0 * j * wave(11));
  return {R * ExpSo3(tremor_rad), p + 0.004 * Eigen::Vector3d(wave(6), wave(7), wave(8))};
}

TruePose Trajectory::BaseAt(double s) const {
  const TrajectoryConfig& c = config_;
  if (c.survey_radius_m > 0.0) return SurveyAt(s);
  auto wave = [&](int i, double t) { return std::sin(2.0 * kPi * freq_[i] * t + phase_[i]); };
  // Walk around the cones: mean orbit rate plus a slow back-and-forth.
  const double azimuth = phase_[0] + c.orbit_rate_deg_s * kDeg * s + 0.6 * wave(0, s);
  const double mid_d = 0.5 * (c.min_distance_m + c.max_distance_m);
  // The look target wanders by up to sqrt(2) * wander_m; the orbit leaves room for it so the
  // camera stays within [min, max] of the cone centroid.
  const double wander_m = 0.06 * mid_d;
  const double half_d = std::max(0.0, 0.5 * (c.max_distance_m - c.min_distance_m) - 1.5 * wander_m);
  const double dist = mid_d + half_d * (0.7 * wave(1, s) + 0.25 * wave(2, s));
  const double mid_e = 0.5 * (c.min_elevation_deg + c.max_elevation_deg) * kDeg;
  const double half_e = 0.5 * (c.max_elevation_deg - c.min_elevation_deg) * kDeg;
  const double elev = mid_e + half_e * (0.75 * wave(3, s) + 0.2 * wave(4, s));
  const Eigen::Vector3d target(wander_m * wave(5, s), wander_m * wave(4, 1.3 * s), c.look_target_height_m);
  const Eigen::Vector3d tremor_m = 0.004 * Eigen::Vector3d(wave(6, s), wave(7, s), wave(8, s));
  const Eigen::Vector3d p =
      target +
      dist * Eigen::Vector3d(std::cos(elev) * std::cos(azimuth), std::cos(elev) * std::sin(azimuth), std::sin(elev)) +
      tremor_m;
  // Look at the target: z forward, x right, y down (camera_optical).
  const Eigen::Vector3d z = (target - p).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R << x, y, z;
  const double j = c.jitter_deg * kDeg;
  const Eigen::Vector3d tremor_rad(j * wave(9, s), j * wave(10, s), 4.0 * j * wave(11, 0.3 * s));  // roll swings
  return {R * ExpSo3(tremor_rad), p};
}

TruePose Trajectory::At(double t) const {
  const double s = Warp(t);
  TruePose pose = BaseAt(s);
  Eigen::Vector3d shake_rad = Eigen::Vector3d::Zero();
  Eigen::Vector3d shake_m = Eigen::Vector3d::Zero();
  double pan_rad = 0.0;
  for (const Segment& seg : config_.segments) {
    if (seg.kind == SegmentKind::kStill || seg.kind == SegmentKind::kLookAt) continue;
    // Shakes and look-aways never overlap stills, so s = t - const inside them.
    const double w = Window(seg, t);
    if (w == 0.0) continue;
    if (seg.kind == SegmentKind::kLookAway) {
      pan_rad += w * seg.amplitude_deg * kDeg;
    } else {
      const double a = seg.amplitude_deg * kDeg, f = 2.0 * kPi * seg.frequency_hz;
      shake_rad += w * a *
                   Eigen::Vector3d(std::sin(f * t + shake_phase_.x()), std::sin(1.13 * f * t + shake_phase_.y()),
                                   0.5 * std::sin(0.87 * f * t + shake_phase_.z()));
      shake_m += w * 0.01 * Eigen::Vector3d(std::sin(0.93 * f * t), std::sin(1.07 * f * t), 0.0);
    }
  }
  // Pan about the world vertical keeps the horizon level while the cones leave the view.
  pose.R_cones_camera = Eigen::AngleAxisd(pan_rad, Eigen::Vector3d::UnitZ()) * pose.R_cones_camera * ExpSo3(shake_rad);
  pose.p_camera_in_cones_m += pose.R_cones_camera * shake_m;
  for (const Segment& seg : config_.segments)
    if (seg.kind == SegmentKind::kLookAt && t > seg.start_s && t < seg.start_s + seg.duration_s)
      pose.R_cones_camera = LookAtSegment(seg, t, pose);
  return pose;
}

Eigen::Matrix3d Trajectory::LookAtSegment(const Segment& seg, double t, const TruePose& walk) const {
  // Chained slerps: each look's smooth step takes the orientation from the previous look to its own;
  // looks not yet begun weigh 0, so between turns the camera holds a pure look-at.
  const Eigen::Quaterniond q_walk(walk.R_cones_camera);
  Eigen::Quaterniond q = q_walk;
  for (const LookKey& k : seg.looks) {
    const double w = SmoothStep((t - seg.start_s - k.start_s) / seg.ramp_s);
    if (w <= 0.0) break;
    const Eigen::Vector3d& p = walk.p_camera_in_cones_m;
    q = q.slerp(w, Eigen::Quaterniond(LookAt(p, k.relative ? Eigen::Vector3d(p + k.target_m) : k.target_m)));
  }
  const double back = SmoothStep((t - (seg.start_s + seg.duration_s - seg.ramp_s)) / seg.ramp_s);
  return q.slerp(back, q_walk).normalized().toRotationMatrix();
}

Eigen::Vector3d Trajectory::OmegaCamera(double t) const {
  const double h = 1e-5;
  const Eigen::Matrix3d dR = At(t - h).R_cones_camera.transpose() * At(t + h).R_cones_camera;
  const Eigen::AngleAxisd aa(dR);
  return aa.angle() * aa.axis() / (2.0 * h);
}

}  // namespace rig_sim
