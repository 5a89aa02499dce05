// The one API: validate, undistort, run the chosen method, check the result
// and attach residuals and covariance.
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "cone_tracker/pose/algorithms.h"
#include "cone_tracker/pose/covariance.h"
#include "cone_tracker/pose/pnp.h"
#include "pose_math/covariance.h"
#include "undistort.h"

namespace cone_tracker {
namespace {

struct MethodInfo {
  PnpMethod method;
  const char* name;
  int min_points;
  bool needs_depth_spread;  // fails on planar model points
  ErrorSpace space;         // where it minimises, and so where its covariance lives
};

const std::array<MethodInfo, 12> kMethods{{
    {PnpMethod::kP3p, "p3p", 4, false, ErrorSpace::kImage},
    {PnpMethod::kDlt, "dlt", 6, true, ErrorSpace::kImage},
    {PnpMethod::kOia, "oia", 4, false, ErrorSpace::kObject},
    {PnpMethod::kMdltIs, "mdlt-is", 6, true, ErrorSpace::kImage},
    {PnpMethod::kMdltOs, "mdlt-os", 6, true, ErrorSpace::kObject},
    {PnpMethod::kSimplexIs, "simplex-is", 6, true, ErrorSpace::kImage},
    {PnpMethod::kSimplexOs, "simplex-os", 6, true, ErrorSpace::kObject},
    {PnpMethod::kEpnp, "epnp", 6, true, ErrorSpace::kImage},
    {PnpMethod::kEpnpGn, "epnp-gn", 6, true, ErrorSpace::kImage},
    {PnpMethod::kSimplexSdp, "simplex-sdp", 6, true, ErrorSpace::kImage},
    {PnpMethod::kCeres, "ceres", 4, false, ErrorSpace::kImage},
    {PnpMethod::kBest, "best", 4, false, ErrorSpace::kImage},
}};

const MethodInfo& Info(PnpMethod method) {
  for (const MethodInfo& m : kMethods)
    if (m.method == method) return m;
  throw std::logic_error("unknown PnpMethod");
}

PnpResult Error(const std::string& message) {
  PnpResult r;
  r.error = message;
  return r;
}

bool Finite(const pose_math::Pose& T) { return T.q.allFinite() && T.t.allFinite(); }

// A linear start that works for the given geometry: the 3-simplex where the
// model has depth, Lu–Hager's own start otherwise.
Estimate LinearStart(const Correspondences& c, bool planar) {
  if (!planar && c.size() >= 6) {
    const Estimate e = SimplexLinear(c, ErrorSpace::kImage);
    if (e.ok && MinDepth(c.model, e.T_camera_model) > 0.0) return e;
  }
  return OrthogonalIteration(c, nullptr, 50, 1e-6);
}

// Linear start + image-space refinement. If the refined RMS residual is
// implausible for the stated noise (a local minimum from a poor linear start,
// common at high noise), restart from OIA, whose convergence basin is wide
// (7.1.2), and from EPnP + Gauss–Newton, and keep the lowest cost.
Estimate Best(const Correspondences& c, const PnpOptions& o, const std::optional<pose_math::Pose>& initial,
              bool planar) {
  const auto refine = [&](const pose_math::Pose& start) {
    return o.robust_loss ? CeresRefine(c, start, true, o.huber_threshold_px, o.max_iterations)
                         : TinyCeresRefine(c, start, o.max_iterations);
  };
  const Estimate start = initial ? Estimate{true, "", *initial, 0, true, 0.0} : LinearStart(c, planar);
  Estimate best = start.ok ? refine(start.T_camera_model) : start;
  int iterations = start.iterations + best.iterations;
  const auto cost_of = [&](const Estimate& e) {
    return e.ok && MinDepth(c.model, e.T_camera_model) > 0.0 ? ImageSpaceCost(c, e.T_camera_model)
                                                             : std::numeric_limits<double>::infinity();
  };
  double best_cost = cost_of(best);
  // ImageSpaceCost is the mean squared 2-D error per point: 2σ² per unit of RMS per coordinate.
  const double gate = 2.0 * std::pow(o.best_restart_rms_factor * o.sigma_px, 2);
  if (best_cost <= gate) return best;
  std::vector<Estimate> starts;
  if (start.ok) starts.push_back(OrthogonalIteration(c, &start.T_camera_model, 200, 1e-10));
  if (!planar && c.size() >= 6) starts.push_back(EpnpGaussNewton(c));
  starts.push_back(OrthogonalIteration(c, nullptr, 200, 1e-10));
  for (const Estimate& s : starts) {
    if (!s.ok) continue;
    const Estimate e = refine(s.T_camera_model);
    iterations += s.iterations + e.iterations;
    const double cost = cost_of(e);
    if (cost < best_cost) best_cost = cost, best = e;
  }
  best.iterations = iterations;
  return best;
}

Estimate Run(const Correspondences& c, const PnpOptions& o, const std::optional<pose_math::Pose>& initial,
             bool planar) {
  const auto refine_null_space = [&](auto linear, auto gauss_newton, ErrorSpace space) {
    Estimate start = initial ? Estimate{true, "", *initial, 0, true, 0.0} : linear(c, space);
    if (!start.ok) return start;
    Estimate e = gauss_newton(c, space, start.T_camera_model, o.max_iterations);
    return e;
  };
  switch (o.method) {
    case PnpMethod::kP3p:
      return P3pFischlerBolles(c);
    case PnpMethod::kDlt:
      return Dlt(c);
    case PnpMethod::kOia: {
      const pose_math::Pose* init = initial ? &*initial : nullptr;
      return OrthogonalIteration(c, init, std::max(o.max_iterations, 200), 1e-12);
    }
    case PnpMethod::kMdltIs:
      return refine_null_space(MdltLinear, MdltGaussNewton, ErrorSpace::kImage);
    case PnpMethod::kMdltOs:
      return refine_null_space(MdltLinear, MdltGaussNewton, ErrorSpace::kObject);
    case PnpMethod::kSimplexIs:
      return refine_null_space(SimplexLinear, SimplexGaussNewton, ErrorSpace::kImage);
    case PnpMethod::kSimplexOs:
      return refine_null_space(SimplexLinear, SimplexGaussNewton, ErrorSpace::kObject);
    case PnpMethod::kEpnp:
      return EpnpLinear(c);
    case PnpMethod::kEpnpGn:
      return EpnpGaussNewton(c);
    case PnpMethod::kSimplexSdp:
      return SimplexSdp(c, ErrorSpace::kImage, o.sdp_eigenvectors, o.sdp_constraint);
    case PnpMethod::kCeres: {
      const Estimate start = initial ? Estimate{true, "", *initial, 0, true, 0.0} : LinearStart(c, planar);
      if (!start.ok) return start;
      Estimate e = CeresRefine(c, start.T_camera_model, o.robust_loss, o.huber_threshold_px, o.max_iterations);
      e.iterations += start.iterations;
      return e;
    }
    case PnpMethod::kBest:
      return Best(c, o, initial, planar);
  }
  return Failure("unknown method");
}

}  // namespace

const std::vector<std::string>& PnpMethodNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const MethodInfo& m : kMethods) v.push_back(m.name);
    return v;
  }();
  return names;
}

std::optional<PnpMethod> PnpMethodFromName(const std::string& name) {
  for (const MethodInfo& m : kMethods)
    if (name == m.name) return m.method;
  return std::nullopt;
}

std::string PnpMethodName(PnpMethod method) { return Info(method).name; }

PnpResult SolvePnp(const CameraModel& camera, const std::vector<Eigen::Vector3d>& model_points,
                   const std::vector<Eigen::Vector2d>& image_points_px, const PnpOptions& options,
                   const std::optional<pose_math::Pose>& initial_T_camera_model) {
  const MethodInfo& info = Info(options.method);
  if (!(camera.fx_px > 0.0) || !(camera.fy_px > 0.0) || !std::isfinite(camera.fx_px) || !std::isfinite(camera.fy_px) ||
      !std::isfinite(camera.cx_px) || !std::isfinite(camera.cy_px))
    return Error("camera: fx, fy must be finite and > 0 and cx, cy finite");
  for (const double k : camera.distortion)
    if (!std::isfinite(k)) return Error("camera: non-finite distortion coefficient");
  const size_t nd = camera.distortion.size();
  if (nd != 0 && nd != 4 && nd != 5 && nd != 8 && nd != 12 && nd != 14)
    return Error("camera: distortion needs 4, 5, 8, 12 or 14 coefficients (OpenCV's model), got " + std::to_string(nd));
  if (model_points.size() != image_points_px.size()) {
    std::ostringstream s;
    s << model_points.size() << " model points but " << image_points_px.size() << " image points";
    return Error(s.str());
  }
  const int n = static_cast<int>(model_points.size());
  if (n < info.min_points) {
    std::ostringstream s;
    s << info.name << " needs at least " << info.min_points << " points, got " << n;
    return Error(s.str());
  }
  Correspondences c;
  c.fx_px = camera.fx_px;
  c.fy_px = camera.fy_px;
  c.model.resize(3, n);
  for (int i = 0; i < n; ++i) {
    if (!model_points[i].allFinite() || !image_points_px[i].allFinite()) {
      std::ostringstream s;
      s << "point " << i << " is not finite (NaN or inf)";
      return Error(s.str());
    }
    c.model.col(i) = model_points[i];
  }
  const Eigen::Vector3d spread = ModelSpread(c.model);
  if (!(spread(0) > 0.0) || spread(1) <= 1e-6 * spread(0)) return Error("model points are collinear (or coincide)");
  const bool planar = spread(2) <= 1e-6 * spread(0);
  if (planar && info.needs_depth_spread) return Error(std::string(info.name) + " needs non-planar model points");
  try {
    if (!NormalizeImagePoints(camera, image_points_px, &c.normalized)) return Error("undistortion failed");
  } catch (const std::exception& ex) {
    return Error(std::string("undistortion failed: ") + ex.what());
  }
  if (initial_T_camera_model) {
    if (!Finite(*initial_T_camera_model)) return Error("initial pose is not finite");
    if (MinDepth(c.model, *initial_T_camera_model) <= 0.0)
      return Error("initial pose puts model points behind the camera");
  }

  Estimate e;
  try {
    e = Run(c, options, initial_T_camera_model, planar);
  } catch (const std::exception& ex) {
    return Error(std::string(info.name) + ": " + ex.what());
  }
  if (!e.ok) return Error(e.error);
  if (!Finite(e.T_camera_model)) return Error(std::string(info.name) + ": non-finite pose");
  if (MinDepth(c.model, e.T_camera_model) <= 0.0)
    return Error(std::string(info.name) + ": solution puts model points behind the camera");

  PnpResult r;
  r.ok = true;
  r.T_camera_model = e.T_camera_model;
  r.iterations = e.iterations;
  r.converged = e.converged;
  r.rotation_nonorthogonality = e.rotation_nonorthogonality;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    r.residuals_px.push_back(ImageResidual(r.T_camera_model, c.model.col(i), c.normalized.col(i), c.fx_px, c.fy_px));
    sum += r.residuals_px.back().squaredNorm();
  }
  r.reproj_rms_px = std::sqrt(sum / n);
  r.covariance_space = info.space;
  if (options.compute_covariance) {
    try {
      r.cov7 = PoseCovarianceQuat(c, r.T_camera_model, info.space, options.sigma_px);
      r.cov6_ros = pose_math::CovarianceRosFromThesis(r.T_camera_model.q, r.cov7);
    } catch (const std::exception& ex) {
      return Error(std::string("covariance: ") + ex.what());
    }
  }
  return r;
}

}  // namespace cone_tracker
