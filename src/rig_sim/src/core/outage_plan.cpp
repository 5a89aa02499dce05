#include "rig_sim/outage_plan.h"

#include "angles.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include <Eigen/Geometry>

namespace rig_sim {
namespace {

constexpr double kFrameS = 1.0 / 30.0;

// A point seen by `cam` at `pose`, in pixels; false behind the camera or so far off the axis that the
// lens polynomial no longer holds (pinhole more than half an image outside).
bool PixelOf(const rig_model::CameraModel& cam, const TruePose& pose, const Eigen::Vector3d& p_m, Eigen::Vector2d* uv) {
  const Eigen::Vector3d c = pose.R_cones_camera.transpose() * (p_m - pose.p_camera_in_cones_m);
  if (c.z() < 0.05) return false;
  const double u = cam.fx_px * c.x() / c.z() + cam.cx_px, v = cam.fy_px * c.y() / c.z() + cam.cy_px;
  const double w = cam.width_px, h = cam.height_px;
  if (u < -0.5 * w || u > 1.5 * w || v < -0.5 * h || v > 1.5 * h) return false;
  return cam.Project(c, uv);
}

bool Inside(const rig_model::CameraModel& cam, const Eigen::Vector2d& uv, double margin_px) {
  return uv.x() >= margin_px && uv.y() >= margin_px && uv.x() < cam.width_px - margin_px &&
         uv.y() < cam.height_px - margin_px;
}

// How a cone looks from `pose`: whether any of its peak, mid and base is within `margin_px` of the
// image (negative margin: inside by that much), whether all of them are, and its peak-base length.
struct ConeView {
  bool touches = false;
  bool whole = false;
  double length_px = 0.0;
};

ConeView ViewOf(const rig_model::CameraModel& cam, const TruePose& pose, const ConeSpec& cone, double margin_px) {
  ConeView v;
  Eigen::Vector2d uv[3];
  bool ok[3];
  const Eigen::Vector3d pts[3] = {cone.peak_m(), cone.mid_m(), cone.base_m};
  v.whole = true;
  for (int i = 0; i < 3; ++i) {
    ok[i] = PixelOf(cam, pose, pts[i], &uv[i]);
    const bool in = ok[i] && Inside(cam, uv[i], margin_px);
    v.touches |= in;
    v.whole &= in;
  }
  if (ok[0] && ok[2]) v.length_px = (uv[0] - uv[2]).norm();
  return v;
}

// Down at the ground just ahead of the feet, toward `heading`: an offset from the camera.
LookKey Down(double start_s, const Eigen::Vector2d& heading, double pitch_deg) {
  const double e = pitch_deg * kDeg;
  const Eigen::Vector2d h = heading.normalized();
  return {start_s, Eigen::Vector3d(std::cos(e) * h.x(), std::cos(e) * h.y(), -std::sin(e)), true};
}

struct Candidate {
  Segment segment;
  PlannedOutage outage;
  double score = -1.0;  // the smaller of the pair's lengths in the image while held
};

class Planner {
 public:
  Planner(const OutagePlanConfig& c, const Scenario& s, const std::vector<Segment>& base) : c_(c), s_(s), base_(base) {}

  // The segment for one outage with the pair (i, j) looked at through `target`, scored; score < 0 when a
  // condition fails.
  Candidate Try(double t0, double away_s, int i, int j, const Eigen::Vector3d& target,
                const Eigen::Vector2d& heading0) const {
    Candidate cand;
    const double r = c_.ramp_s, t_turn = t0 + r + away_s;
    Segment& seg = cand.segment;
    seg.kind = SegmentKind::kLookAt;
    seg.start_s = t0;
    seg.ramp_s = r;
    seg.duration_s = r + away_s + r + c_.pair_hold_s + r;
    const Trajectory walk(WithSegments({}));
    const Eigen::Vector2d to_pair = (target - walk.At(t_turn).p_camera_in_cones_m).head<2>();
    seg.looks = {Down(0.0, heading0, c_.down_pitch_deg),
                 Down(r + 0.5 * (away_s - r), to_pair, c_.down_pitch_deg),
                 {r + away_s, target, false}};
    const Trajectory traj(WithSegments({seg}));
    const rig_model::CameraModel& cam = s_.camera.model;
    const auto& cones = s_.scene.cones;
    double score = 1e9;
    // First the hold's ends alone (most candidates fail there), then every frame in order.
    for (double t : {t_turn + r, t_turn + r + c_.pair_hold_s}) {
      const TruePose pose = traj.At(t);
      for (size_t k = 0; k < cones.size(); ++k) {
        const bool pair = static_cast<int>(k) == i || static_cast<int>(k) == j;
        const ConeView v = ViewOf(cam, pose, cones[k], pair ? c_.pair_margin_px : -c_.other_margin_px);
        if (pair ? (!v.whole || v.length_px < c_.pair_min_px) : (v.touches && v.length_px > c_.other_max_px))
          return cand;
      }
    }
    // Looking down: no cone near the image. The turn up: at most two resolvable cones whole in the image
    // (any two: one may pass before the pair arrives). The hold: the pair whole, well inside and tall, no other cone
    // resolvable.
    for (double t = t0 + r; t <= t_turn + r + c_.pair_hold_s; t += kFrameS) {
      const TruePose pose = traj.At(t);
      const bool down = t < t_turn, hold = t >= t_turn + r;
      int resolvable = 0;
      for (size_t k = 0; k < cones.size(); ++k) {
        const bool pair = static_cast<int>(k) == i || static_cast<int>(k) == j;
        if (pair && hold) {
          const ConeView v = ViewOf(cam, pose, cones[k], c_.pair_margin_px);
          if (!v.whole || v.length_px < c_.pair_min_px) return cand;
          score = std::min(score, v.length_px);
          continue;
        }
        const ConeView v = ViewOf(cam, pose, cones[k], -c_.other_margin_px);
        if (!v.touches) continue;
        if (down || (hold && v.length_px > c_.other_max_px)) return cand;
        const bool whole = ViewOf(cam, pose, cones[k], 0.0).whole;  // a cone cut by the border fails the border gate
        if (whole && v.length_px > c_.other_max_px && ++resolvable > 2) return cand;
      }
    }
    // No turn faster than the rig's gyros measure: a slerp between looks nearly 180 deg apart may take
    // the other way round from one frame to the next (seen: a 112 deg jump on a 30-cone layout).
    const double dt = 0.01;
    for (double t = t0; t < t0 + seg.duration_s; t += dt) {
      const Eigen::AngleAxisd step(traj.At(t).R_cones_camera.transpose() * traj.At(t + dt).R_cones_camera);
      if (step.angle() / dt > c_.max_rate_deg_s * kDeg) return cand;
    }
    cand.score = score;
    cand.outage = {t0, away_s, t_turn, t_turn + r + c_.pair_hold_s, i, j};
    return cand;
  }

  TrajectoryConfig WithSegments(const std::vector<Segment>& extra) const {
    TrajectoryConfig t = s_.trajectory;
    t.segments = base_;
    t.segments.insert(t.segments.end(), extra.begin(), extra.end());
    return t;
  }

 private:
  const OutagePlanConfig& c_;
  const Scenario& s_;
  std::vector<Segment> base_;
};

// The best outage starting at t0 whose stretch looking down lasts drawn_s, moved by up to shift_max_s.
Candidate PlanOne(const OutagePlanConfig& config, const Scenario& s, const Planner& planner, double t0,
                  double drawn_s) {
  const Trajectory walk(planner.WithSegments({}));
  const Eigen::Vector2d heading0 = (walk.At(t0).R_cones_camera.col(2)).head<2>();
  const auto& cones = s.scene.cones;
  Candidate best;
  for (int step = 0; step <= 2 * static_cast<int>(std::floor(config.shift_max_s / 0.5)) && best.score < 0; ++step) {
    const double shift = 0.5 * ((step + 1) / 2) * (step % 2 == 1 ? 1.0 : -1.0);
    const double away_s = drawn_s + shift;
    if (away_s < 2.0 || away_s > 8.0) continue;
    if (t0 + 3.0 * config.ramp_s + away_s + config.pair_hold_s > s.trajectory.duration_s) continue;
    const Eigen::Vector3d p = walk.At(t0 + away_s + 2.0 * config.ramp_s).p_camera_in_cones_m;
    for (size_t i = 0; i < cones.size(); ++i) {
      for (size_t j = i + 1; j < cones.size(); ++j) {
        const double ri = (cones[i].base_m - p).norm(), rj = (cones[j].base_m - p).norm();
        if (std::min(ri, rj) < config.min_range_m || std::max(ri, rj) > config.max_range_m) continue;
        const Eigen::Vector3d mid = 0.5 * (cones[i].base_m + cones[j].base_m);
        const Eigen::Vector3d side = Eigen::Vector3d::UnitZ().cross(mid - p).normalized();
        // Lower look targets tilt the view down, which puts the cones behind the pair above the image;
        // a look to the side of the pair's middle can leave a third cone out.
        for (double lateral_m : {0.0, -0.6, 0.6}) {
          for (double dz : {0.3, 0.0, -0.5, -1.0, -1.5, -2.5}) {
            Candidate c = planner.Try(t0, away_s, static_cast<int>(i), static_cast<int>(j),
                                      mid + lateral_m * side + Eigen::Vector3d(0, 0, dz), heading0);
            if (c.score > best.score) best = c;
          }
        }
      }
    }
  }
  return best;
}

}  // namespace

bool PlanOutages(const OutagePlanConfig& config, Scenario* s, std::vector<PlannedOutage>* planned, std::string* error) {
  std::vector<Segment> segments;
  for (const Segment& seg : s->trajectory.segments)
    if (seg.kind != SegmentKind::kLookAt) segments.push_back(seg);
  if (planned) planned->clear();
  std::mt19937_64 rng(s->trajectory.seed * 0x2545F4914F6CDD1Dull + 3);
  std::uniform_real_distribution<double> away_draw(config.min_away_s, config.max_away_s);
  double previous_end_s = -1e9;
  for (size_t n = 0; n < config.starts_s.size(); ++n) {
    const double drawn_s = away_draw(rng);
    const Planner planner(config, *s, segments);
    Candidate best;
    // The walk goes on: a later start meets other cones. An outage starts 5 s after the last one's end
    // at the earliest (the tracker is back on more cones by then).
    const double first_s = std::max(config.starts_s[n], previous_end_s + 5.0);
    for (double t0 = first_s; t0 <= config.starts_s[n] + config.start_window_s && best.score < 0; t0 += 1.0)
      best = PlanOne(config, *s, planner, t0, drawn_s);
    if (best.score < 0) {
      std::ostringstream msg;
      msg << s->name << ": no view of exactly two cones found for an outage starting at " << config.starts_s[n] << "-"
          << config.starts_s[n] + config.start_window_s << " s (layout of " << s->scene.cones.size()
          << " cones, the return moved by up to " << config.shift_max_s << " s): no pair of cones "
          << config.min_range_m << "-" << config.max_range_m << " m from the walk fills the view alone";
      if (error) *error = msg.str();
      return false;
    }
    segments.push_back(best.segment);
    previous_end_s = best.segment.start_s + best.segment.duration_s;
    if (planned) planned->push_back(best.outage);
  }
  s->trajectory.segments = segments;
  return true;
}

}  // namespace rig_sim
