#include "initialise.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>

#include "place_refine.h"
#include "pose_math/quaternion.h"

namespace cone_survey {
namespace {

// A rotation taking `up` (camera frame) to +z, with the camera's forward axis toward +x.
Eigen::Matrix3d LevelRotation(const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = up.normalized();
  Eigen::Vector3d x = Eigen::Vector3d::UnitZ() - z * z.z();  // camera forward, levelled
  if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitX() - z * z.x();
  x.normalize();
  Eigen::Matrix3d R_camera_world;
  R_camera_world << x, z.cross(x), z;  // columns: world axes in the camera
  return R_camera_world.transpose();
}

// The first linear pass knows no ranges: its ray rows are in metres at about this distance.
constexpr double kNominalRangeM = 3.0;
constexpr double kGravityM_s2 = 9.80665;

struct Placed {  // a track placed by the linear solve
  int track;
  Eigen::Vector3d base;
  double height;
  int count;
  double first_s, last_s;
};

struct Group {  // tracks of one cone
  std::vector<int> placed;
  Eigen::Vector3d base = Eigen::Vector3d::Zero();
  double height = 0.0;
  int count = 0;
  double first_s = 1e300, last_s = -1e300;
  void Add(const Placed& p, int index) {
    base = (base * count + p.base * p.count) / (count + p.count);
    height = (height * count + p.height * p.count) / (count + p.count);
    count += p.count;
    first_s = std::min(first_s, p.first_s);
    last_s = std::max(last_s, p.last_s);
    placed.push_back(index);
  }
};

// Linear structure from motion with known rotations: every sighting's peak and base rays through
// the camera, S(d) (X - p_k) = 0, with X = B + h z for the peak and X = B (+ tau h u, the base circle's
// front toward the camera along u from the previous pass, 3.16) for the base. Unknowns: camera
// positions (the first at the origin), per track B and h unless fixed_h gives it. False when singular.
bool SolveTracks(const SurveyInput& in, const std::vector<int>& frames, const std::vector<Eigen::Matrix3d>& R,
                 const std::vector<Use>& uses, const std::vector<int>& unit, const std::vector<double>& fixed_h,
                 const std::vector<std::vector<double>>& weights, double tau,
                 const std::vector<Eigen::Vector3d>& prev_cameras, const std::vector<Eigen::Vector3d>& prev_bases,
                 const std::vector<Eigen::Vector3d>& dv, double accel_weight, std::vector<Eigen::Vector3d>* cameras,
                 std::vector<Eigen::Vector3d>* bases, std::vector<double>* heights) {
  const int K = static_cast<int>(frames.size()), T = static_cast<int>(uses.size());
  const int U = *std::max_element(unit.begin(), unit.end()) + 1;
  std::vector<int> h_index(T, -1);
  int n = 3 * (K - 1) + 3 * U;
  for (int t = 0; t < T; ++t)
    if (std::isnan(fixed_h[t])) h_index[t] = n++;
  // The accelerometer in the solution's units: one scale (metres per unit until the heights fix it)
  // and one constant acceleration error (g's magnitude, the accelerometer's bias).
  const int accel_scale_index = n++, accel_bias_index = n;
  n += 3;
  std::vector<Eigen::Triplet<double>> trip;
  std::vector<double> rhs;
  Eigen::Matrix3d K_inv = Eigen::Matrix3d::Identity();
  K_inv(0, 0) = 1.0 / in.camera.fx_px, K_inv(1, 1) = 1.0 / in.camera.fy_px;
  K_inv(0, 2) = -in.camera.cx_px / in.camera.fx_px, K_inv(1, 2) = -in.camera.cy_px / in.camera.fy_px;
  int row = 0;
  for (int t = 0; t < T; ++t) {
    for (size_t i = 0; i < uses[t].sightings.size(); ++i) {
      const auto [k, s] = uses[t].sightings[i];
      const ConeSighting& c = in.frames[frames[k]].cones[s];
      Eigen::Vector3d u = Eigen::Vector3d::Zero();  // horizontal, from the cone toward the camera
      double w = weights[t][i];                     // robust; rows in radians once ranges are known
      if (!prev_bases.empty()) {
        u = prev_cameras[k] - prev_bases[t];
        w /= std::max(0.5, u.norm());
        u.z() = 0.0;
        u = u.norm() > 1e-6 && tau > 0.0 ? Eigen::Vector3d(u.normalized()) : Eigen::Vector3d::Zero();
      }
      for (int point = 0; point < 2; ++point) {
        const Eigen::Vector2d px = point == 0 ? c.peak_px : c.base_px;
        const Eigen::Matrix3d S = w * pose_math::Skew((R[k] * K_inv * px.homogeneous()).normalized());
        // The point's offset from B per unit of height: z for the peak, tau u for the base.
        const Eigen::Vector3d per_h = point == 0 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d(tau * u);
        const Eigen::Vector3d S_h = S * per_h;
        for (int r = 0; r < 3; ++r) {
          for (int j = 0; j < 3; ++j) {
            trip.emplace_back(row + r, 3 * (K - 1) + 3 * unit[t] + j, S(r, j));
            if (k > 0) trip.emplace_back(row + r, 3 * (k - 1) + j, -S(r, j));
          }
          if (h_index[t] >= 0) trip.emplace_back(row + r, h_index[t], S_h[r]);
          rhs.push_back(h_index[t] >= 0 ? 0.0 : -S_h[r] * fixed_h[t]);
        }
        row += 3;
      }
    }
  }
  // The accelerometer: the second difference of the camera positions is the velocity change it
  // measured between the frames (dv, m/s; the lever arm neglected), times the solution's scale, plus
  // one constant acceleration error. One scale for the whole window, so it holds the scale where few
  // cones link one stretch of the walk to the next: without it the scale drifted along hand-overs of
  // short tracks (an 11-cone layout's first window placed heights from 0.55 to 2.2 times their true
  // ones). Rows in the units of the ray rows: accel_weight is (their sigma) / (the accelerometer's
  // sigma in m/s^2).
  const double range_m = prev_bases.empty() ? kNominalRangeM : 1.0;  // the first pass's rows are in metres
  for (int k = 1; k + 1 < K; ++k) {
    const double ta = in.frames[frames[k - 1]].stamp_s, tb = in.frames[frames[k]].stamp_s,
                 tc = in.frames[frames[k + 1]].stamp_s;
    if (tc - ta > 0.5 || !dv[k].allFinite()) continue;
    const double wa = 1.0 / (tb - ta), wc = 1.0 / (tc - tb), span = (tc - ta) / 2.0;
    const double scale = range_m * accel_weight / span;
    const int idx[3] = {k - 1, k, k + 1};
    const double coef[3] = {wa * scale, -(wa + wc) * scale, wc * scale};
    for (int r = 0; r < 3; ++r) {
      for (int i = 0; i < 3; ++i)
        if (idx[i] > 0) trip.emplace_back(row + r, 3 * (idx[i] - 1) + r, coef[i]);
      trip.emplace_back(row + r, accel_scale_index, -dv[k][r] * scale);
      trip.emplace_back(row + r, accel_bias_index + r, -span * scale);
      rhs.push_back(0.0);
    }
    row += 3;
  }
  Eigen::SparseMatrix<double> A(row, n);
  A.setFromTriplets(trip.begin(), trip.end());
  const Eigen::VectorXd b = Eigen::Map<Eigen::VectorXd>(rhs.data(), row);
  Eigen::SparseMatrix<double> N = A.transpose() * A;
  for (int i = 0; i < n; ++i) N.coeffRef(i, i) += 1e-9;  // frames or tracks not tied to the rest stay finite
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(N);
  const Eigen::VectorXd x = ldlt.solve(A.transpose() * b);
  if (ldlt.info() != Eigen::Success || !x.allFinite()) return false;
  cameras->assign(K, Eigen::Vector3d::Zero());
  for (int k = 1; k < K; ++k) (*cameras)[k] = x.segment<3>(3 * (k - 1));
  bases->resize(T);
  heights->resize(T);
  for (int t = 0; t < T; ++t) {
    (*bases)[t] = x.segment<3>(3 * (K - 1) + 3 * unit[t]);
    (*heights)[t] = h_index[t] >= 0 ? x[h_index[t]] : fixed_h[t];
  }
  return true;
}

// Huber weights of every sighting from its rays' angular errors at the solution (threshold: three
// times the median error), so that a track that jumped to another cone pulls little.
std::vector<std::vector<double>> RobustWeights(const SurveyInput& in, const std::vector<int>& frames,
                                               const std::vector<Eigen::Matrix3d>& R, const std::vector<Use>& uses,
                                               const std::vector<Eigen::Vector3d>& cameras,
                                               const std::vector<Eigen::Vector3d>& bases,
                                               const std::vector<double>& heights) {
  std::vector<std::vector<double>> err(uses.size()), w(uses.size());
  std::vector<double> all;
  for (size_t t = 0; t < uses.size(); ++t) {
    for (const auto& [k, s] : uses[t].sightings) {
      const ConeSighting& c = in.frames[frames[k]].cones[s];
      double e = 0.0;
      for (int point = 0; point < 2; ++point) {
        const Eigen::Vector2d px = point == 0 ? c.peak_px : c.base_px;
        const Eigen::Vector3d d = R[k] * Eigen::Vector3d((px.x() - in.camera.cx_px) / in.camera.fx_px,
                                                         (px.y() - in.camera.cy_px) / in.camera.fy_px, 1.0);
        const Eigen::Vector3d X = bases[t] + (point == 0 ? heights[t] : 0.0) * Eigen::Vector3d::UnitZ() - cameras[k];
        e = std::max(e, d.normalized().cross(X.normalized()).norm());
      }
      err[t].push_back(e);
      all.push_back(e);
    }
  }
  std::nth_element(all.begin(), all.begin() + all.size() / 2, all.end());
  const double threshold = std::max(1e-4, 3.0 * all[all.size() / 2]);
  for (size_t t = 0; t < uses.size(); ++t)
    for (double e : err[t]) w[t].push_back(e < threshold ? 1.0 : std::sqrt(threshold / e));
  return w;
}

// Tracks of one cone, longest first: a track joins the nearest group whose height is within 30 % of
// its own and whose base is within 0.6 of the taller height or 0.5 m (a short track is placed less
// well; cones stand at least 0.5 m apart). Sorts `placed` by sightings, longest first.
std::vector<Group> GroupTracks(std::vector<Placed>* placed) {
  std::sort(placed->begin(), placed->end(), [](const Placed& a, const Placed& b) { return a.count > b.count; });
  std::vector<Group> groups;
  for (int i = 0; i < static_cast<int>(placed->size()); ++i) {
    const Placed& p = (*placed)[i];
    int best = -1;
    double best_d = 1e300;
    for (int g = 0; g < static_cast<int>(groups.size()); ++g) {
      const double d = (groups[g].base - p.base).head<2>().norm();
      const double ratio = p.height / groups[g].height;
      if (d < std::max(0.5, 0.6 * std::max(p.height, groups[g].height)) && ratio > 0.7 && ratio < 1.0 / 0.7 &&
          d < best_d)
        best = g, best_d = d;
    }
    if (best < 0) {
      groups.emplace_back();
      best = static_cast<int>(groups.size()) - 1;
    }
    groups[best].Add(p, i);
  }
  return groups;
}

// The scale that puts most groups (by sightings) on an inventory height, each height taking no more
// groups than the inventory has cones of it: 0.30, 0.46 and 0.71 m are each 1.54 times the last, so
// a scale off by that factor also puts many groups on some height, but on the wrong number of them.
double ScaleFromHeights(const std::vector<Group>& groups, const Inventory& inv, double tol) {
  std::map<int, int> count_of;  // inventory height (mm) -> cones
  for (const rig_model::ConeSpec& c : inv.cones) ++count_of[static_cast<int>(std::lround(c.height_m * 1000.0))];
  auto score = [&](double scale) {
    std::map<int, std::vector<double>> votes;  // per height, each matching group's vote
    for (const Group& g : groups) {
      int best_key = -1;
      double best = tol;
      for (const auto& [key, n] : count_of) {
        const double e = std::abs(std::log(scale * g.height / (key / 1000.0)));
        if (e < best) best = e, best_key = key;
      }
      if (best_key >= 0) votes[best_key].push_back(g.count * (1.0 - best / tol));
    }
    double total = 0.0;
    for (auto& [key, v] : votes) {
      std::sort(v.rbegin(), v.rend());
      for (int i = 0; i < std::min<int>(count_of[key], static_cast<int>(v.size())); ++i) total += v[i];
    }
    return total;
  };
  double scale = 1.0, best_score = -1.0;
  for (const Group& g : groups)
    for (const rig_model::ConeSpec& c : inv.cones) {
      const double s = c.height_m / g.height, v = score(s);
      if (v > best_score) best_score = v, scale = s;
    }
  return scale;
}

}  // namespace

bool InitialiseSurvey(const SurveyInput& in, const Inventory& inv, const SurveyConfig& config,
                      const GyroIntegrator& gyro, const Eigen::Vector3d& bias_imu, const std::vector<Track>& tracks,
                      InitialSurvey* out, std::string* error) {
  const double t0 = in.frames.front().stamp_s;
  // Adjusted frames: frames with a tracked sighting, at most adjust_rate_hz.
  std::vector<int> frame_tracks_count(in.frames.size(), 0);
  for (const Track& t : tracks)
    for (const auto& s : t.sightings) ++frame_tracks_count[s.first];
  std::vector<int> frames;
  std::vector<int> adjusted_index(in.frames.size(), -1);
  double next_s = -1e300;
  for (int f = 0; f < static_cast<int>(in.frames.size()); ++f) {
    if (frame_tracks_count[f] == 0 || in.frames[f].stamp_s < next_s) continue;
    adjusted_index[f] = static_cast<int>(frames.size());
    frames.push_back(f);
    next_s = in.frames[f].stamp_s + 1.0 / config.adjust_rate_hz - 1e-6;
  }
  if (frames.size() < 3) {
    *error = "the walk shows cones in " + std::to_string(frames.size()) + " frames: nothing to survey";
    return false;
  }
  // Rotations from the gyro, levelled by the accelerometer at the first adjusted frame.
  Eigen::Vector3d up;
  if (!gyro.UpInCamera(in.frames[frames[0]].stamp_s, 0.05, &up)) {
    *error = "no IMU samples at the first frame with cones (t = " + std::to_string(in.frames[frames[0]].stamp_s - t0) +
             " s): the IMU must cover the walk";
    return false;
  }
  std::vector<Eigen::Matrix3d> R(frames.size());
  R[0] = LevelRotation(up);
  for (size_t k = 1; k < frames.size(); ++k)
    R[k] = R[k - 1] * gyro.Delta(in.frames[frames[k - 1]].stamp_s, in.frames[frames[k]].stamp_s, bias_imu);

  // The accelerometer's velocity change around each adjusted frame, between the midpoints to its
  // neighbours, gravity taken off (NaN at the ends).
  std::vector<Eigen::Vector3d> dv(frames.size(), Eigen::Vector3d::Constant(NAN));
  for (size_t k = 1; k + 1 < frames.size(); ++k) {
    const double ta = in.frames[frames[k - 1]].stamp_s, tb = in.frames[frames[k]].stamp_s,
                 tc = in.frames[frames[k + 1]].stamp_s;
    const double a = 0.5 * (ta + tb), c = 0.5 * (tb + tc);
    dv[k] = gyro.SpecificForceIntegral(a, c, tb, R[k], bias_imu) - Eigen::Vector3d(0, 0, kGravityM_s2 * (c - a));
  }
  const double accel_weight = config.sigma_px / in.camera.fx_px / config.accel_noise_m_s2;
  // Tracks with two or more adjusted sightings.
  std::vector<Use> uses;
  std::vector<Group> groups;
  std::vector<Placed> placed_all;
  for (int t = 0; t < static_cast<int>(tracks.size()); ++t) {
    Use u{t, {}};
    for (const auto& s : tracks[t].sightings)
      if (adjusted_index[s.first] >= 0) u.sightings.emplace_back(adjusted_index[s.first], s.second);
    if (u.sightings.size() >= 2) uses.push_back(u);
  }
  if (uses.empty()) {
    *error = "no cone was followed over two or more frames: walk slower, or check the camera and the detector";
    return false;
  }
  // Place the tracks over a growing window of the walk. In the first window (6 s of motion) the
  // heights are free (the longest track's is the unit) and the scale comes from the inventory's
  // heights; from then on every track whose height falls in an inventory class keeps that height, so
  // the solution stays metric and the scale cannot drift as tracks hand over along the walk.
  const int K = static_cast<int>(frames.size()), T = static_cast<int>(uses.size());
  std::map<int, std::vector<int>> class_inv, class_groups;  // key: height in mm
  for (int i = 0; i < static_cast<int>(inv.cones.size()); ++i)
    class_inv[static_cast<int>(std::lround(inv.cones[i].height_m * 1000.0))].push_back(i);
  const double tol = std::log(1.0 + config.height_tolerance);
  auto nearest_class = [&](double h) {  // height in mm, or -1 when none is within the tolerance
    int best_key = -1;
    double best = tol;
    for (const auto& [key, members] : class_inv) {
      const double e = std::abs(std::log(h / (key / 1000.0)));
      if (e < best) best = e, best_key = key;
    }
    return best_key;
  };
  std::vector<double> fixed_h(T, NAN);
  std::vector<Eigen::Vector3d> cameras, bases, prev_cameras, prev_bases;
  std::vector<double> heights;
  const double end_s = in.frames[frames.back()].stamp_s - t0;
  // Frames before the rig moved add no parallax: the solves start at the last still frame (k0), and
  // the frames before it take its position.
  double first_window_s = 6.0;
  int k0 = 0;
  for (int k = 0; k < K; ++k)  // six seconds after the first frame that moved (R: the gyro's rotations)
    if (!(R[0].transpose() * R[k]).isApprox(Eigen::Matrix3d::Identity(), 1e-3)) {
      first_window_s = in.frames[frames[k]].stamp_s - t0 + 6.0;
      k0 = std::max(0, k - 1);
      break;
    }
  for (double window_s = first_window_s;; window_s += 3.0) {
    const bool last = window_s >= end_s;
    int Kw = 0;
    while (Kw < K && in.frames[frames[Kw]].stamp_s - t0 <= window_s + 1e-9) ++Kw;
    std::vector<int> frames_w(frames.begin() + k0, frames.begin() + Kw);
    std::vector<Use> uses_w;
    std::vector<int> track_of;  // uses_w -> uses
    for (int t = 0; t < T; ++t) {
      Use u{uses[t].track, {}};
      for (const auto& [k, s] : uses[t].sightings)
        if (k >= k0 && k < Kw) u.sightings.emplace_back(k - k0, s);
      if (u.sightings.size() >= 2) uses_w.push_back(u), track_of.push_back(t);
    }
    if (uses_w.empty() && !last) continue;
    if (uses_w.empty()) {
      *error = "no cone was followed over two or more frames";
      return false;
    }
    const int Tw = static_cast<int>(uses_w.size());
    std::vector<double> fixed_w(Tw);
    for (int i = 0; i < Tw; ++i) fixed_w[i] = fixed_h[track_of[i]];
    const bool metric = std::any_of(fixed_w.begin(), fixed_w.end(), [](double h) { return !std::isnan(h); });
    if (!metric)  // the longest track's height is the unit
      fixed_w[std::max_element(uses_w.begin(), uses_w.end(),
                               [](const Use& a, const Use& b) { return a.sightings.size() < b.sightings.size(); }) -
              uses_w.begin()] = 1.0;
    std::vector<int> unit(Tw);
    for (int i = 0; i < Tw; ++i) unit[i] = i;
    std::vector<std::vector<double>> weights(Tw);
    for (int i = 0; i < Tw; ++i) weights[i].assign(uses_w[i].sightings.size(), 1.0);
    std::vector<Eigen::Matrix3d> R_w(R.begin() + k0, R.begin() + Kw);
    // Twice: the second time with the robust weights of the first (and, in the last window, the base
    // points moved to the cone's front, 3.16).
    for (int robust = 0; robust < 2; ++robust) {
      if (!SolveTracks(in, frames_w, R_w, uses_w, unit, fixed_w, weights, last && robust ? 1.0 / 7.0 : 0.0,
                       prev_cameras, prev_bases, std::vector<Eigen::Vector3d>(dv.begin() + k0, dv.begin() + Kw),
                       accel_weight, &cameras, &bases, &heights)) {
        *error = "the walk's frames and cones do not form one connected survey (linear solve failed)";
        return false;
      }
      weights = RobustWeights(in, frames_w, R_w, uses_w, cameras, bases, heights);
      prev_cameras = cameras;
      prev_bases = bases;
    }
    RefinePlacement(in, frames_w, R_w, uses_w, fixed_w, std::vector<Eigen::Vector3d>(dv.begin() + k0, dv.begin() + Kw),
                    config, &cameras, &bases, &heights);
    prev_cameras.clear();
    prev_bases.clear();
    double scale = 1.0;
    if (!metric) {
      std::vector<Placed> placed;
      for (int i = 0; i < Tw; ++i)
        if (heights[i] > 0.0)
          placed.push_back({i, bases[i], heights[i], static_cast<int>(uses_w[i].sightings.size()), 0, 0});
      const std::vector<Group> g = GroupTracks(&placed);
      scale = ScaleFromHeights(g, inv, tol);
    }
    for (int i = 0; i < Tw; ++i) {
      if (!std::isnan(fixed_h[track_of[i]]) || !(heights[i] > 0.0)) continue;
      const int key = nearest_class(scale * heights[i]);
      if (key >= 0) fixed_h[track_of[i]] = key / 1000.0;
    }
    if (!last) continue;
    // The last window is the whole walk: the tracks as placed, grouped into cones.
    std::vector<Placed> placed;
    for (int i = 0; i < Tw; ++i) {
      if (!(heights[i] > 0.0)) continue;
      // A track seen mostly from one spot (the still start) has little parallax: its place is a guess.
      const auto& seen = uses_w[i].sightings;
      const Eigen::Vector3d c0 = cameras[seen[seen.size() / 4].first], c1 = cameras[seen[3 * seen.size() / 4].first];
      if ((c1 - c0).norm() < 0.05 * (bases[i] - c0).norm()) continue;
      const double first = in.frames[frames_w[seen.front().first]].stamp_s - t0;
      const double last_seen = in.frames[frames_w[seen.back().first]].stamp_s - t0;
      placed.push_back(
          {i, scale * bases[i], scale * heights[i], static_cast<int>(uses_w[i].sightings.size()), first, last_seen});
    }
    for (Eigen::Vector3d& c : cameras) c *= scale;
    cameras.insert(cameras.begin(), k0, cameras.front());  // the still start
    for (Use& u : uses_w)
      for (auto& sk : u.sightings) sk.first += k0;
    uses = uses_w;
    groups = GroupTracks(&placed);
    placed_all = placed;
    break;
  }
  std::vector<Placed>& placed = placed_all;
  std::vector<int> unmatched_groups;
  for (int g = 0; g < static_cast<int>(groups.size()); ++g) {
    if (groups[g].count < 2 * config.min_track_frames) continue;  // a glimpse: too little to be a cone
    const int key = nearest_class(groups[g].height);
    if (key < 0)
      unmatched_groups.push_back(g);
    else
      class_groups[key].push_back(g);
  }
  // Where a found cone is, for the messages: relative to the first adjusted camera.
  auto where = [&](const Group& g) {
    std::ostringstream s;
    s.precision(2);
    s << std::fixed << "a cone of " << g.height << " m at (" << g.base.x() << ", " << g.base.y()
      << ") m from the first camera, seen " << g.first_s << "-" << g.last_s << " s";
    return s.str();
  };
  std::ostringstream problems;
  double lo_m = 1e9, hi_m = 0.0;  // heights a cone of the inventory could be mistaken for
  for (const rig_model::ConeSpec& c : inv.cones)
    lo_m = std::min(lo_m, 0.6 * c.height_m), hi_m = std::max(hi_m, 1.5 * c.height_m);
  for (int g : unmatched_groups)
    if (groups[g].height > lo_m && groups[g].height < hi_m)
      problems << "\n  found " << where(groups[g]) << ": no inventory cone has that height";
  out->base_m.assign(inv.cones.size(), Eigen::Vector3d::Zero());
  std::vector<int> group_of_cone(inv.cones.size(), -1);
  for (auto& [key, members] : class_inv) {
    std::vector<int> found = class_groups[key];
    std::sort(found.begin(), found.end(), [&](int a, int b) { return groups[a].count > groups[b].count; });
    if (found.size() > members.size()) {
      problems << "\n  " << found.size() << " cones of " << key / 1000.0 << " m found, the inventory lists "
               << members.size() << ":";
      for (int g : found) problems << "\n    " << where(groups[g]);
      problems << "\n    (a cone that moved during the walk shows twice: once before, once after)";
    } else if (found.size() < members.size()) {
      problems << "\n  not found:";
      for (size_t i = found.size(); i < members.size(); ++i) problems << " " << inv.Name(members[i]);
    }
    for (size_t i = 0; i < std::min(found.size(), members.size()); ++i) group_of_cone[members[i]] = found[i];
  }
  if (!problems.str().empty()) {
    *error = "the walk does not match the inventory (" + std::to_string(inv.cones.size()) + " cones):" + problems.str();
    return false;
  }
  // The output frame: origin at the origin cone, +x toward the +x cone, z up.
  const Eigen::Vector3d origin = groups[group_of_cone[inv.origin]].base;
  const Eigen::Vector3d toward = groups[group_of_cone[inv.x_axis]].base - origin;
  const Eigen::Matrix3d R_out_world =
      Eigen::AngleAxisd(-std::atan2(toward.y(), toward.x()), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  out->frames = frames;
  out->R_world_camera.resize(K);
  out->p_camera_m.resize(K);
  for (int k = 0; k < K; ++k) {
    out->R_world_camera[k] = R_out_world * R[k];
    out->p_camera_m[k] = R_out_world * (cameras[k] - origin);
  }
  for (size_t i = 0; i < inv.cones.size(); ++i) out->base_m[i] = R_out_world * (groups[group_of_cone[i]].base - origin);
  out->base_m[inv.origin].setZero();
  out->base_m[inv.x_axis].y() = 0.0;
  // Observations: every adjusted sighting of every track in an assigned group.
  std::vector<int> cone_of_group(groups.size(), -1);
  for (size_t i = 0; i < inv.cones.size(); ++i) cone_of_group[group_of_cone[i]] = static_cast<int>(i);
  out->observations.clear();
  for (int g = 0; g < static_cast<int>(groups.size()); ++g) {
    if (cone_of_group[g] < 0) continue;
    for (int pi : groups[g].placed)
      for (const auto& [k, s] : uses[placed[pi].track].sightings)
        out->observations.push_back({k, cone_of_group[g], in.frames[frames[k]].cones[s]});
  }
  return true;
}

}  // namespace cone_survey
