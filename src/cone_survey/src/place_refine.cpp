#include "place_refine.h"

#include <array>
#include <cmath>

#include <ceres/ceres.h>

namespace cone_survey {
namespace {

// A peak (B + h z) or base (B) seen from camera p with the known rotation: pixel error (3.10 without
// distortion: the sightings are undistorted).
struct RayCost {
  Eigen::Matrix3d R_camera_world;
  Eigen::Vector2d px;
  double fx, fy, cx, cy, inv_sigma;
  bool peak;
  template <typename T>
  bool operator()(const T* p, const T* b, const T* h, T* r) const {
    Eigen::Matrix<T, 3, 1> X(b[0] - p[0], b[1] - p[1], b[2] - p[2]);
    if (peak) X.z() += h[0];
    const Eigen::Matrix<T, 3, 1> c = R_camera_world.cast<T>() * X;
    if (!(c.z() > T(1e-6))) return false;
    r[0] = (T(fx) * c.x() / c.z() + T(cx) - T(px.x())) * T(inv_sigma);
    r[1] = (T(fy) * c.y() / c.z() + T(cy) - T(px.y())) * T(inv_sigma);
    return true;
  }
};

// The second difference of three camera positions (solution units) against the accelerometer's
// velocity change dv (m/s) over `span` seconds: (D(p) / scale - dv - bias span) / (sigma span).
struct AccelCost {
  Eigen::Vector3d dv;
  double wa, wc, span, inv_sigma;
  template <typename T>
  bool operator()(const T* pa, const T* pb, const T* pc, const T* scale, const T* bias, T* r) const {
    for (int i = 0; i < 3; ++i) {
      const T d = (T(wc) * (pc[i] - pb[i]) - T(wa) * (pb[i] - pa[i])) / scale[0];
      r[i] = (d - T(dv[i]) - bias[i] * T(span)) * T(inv_sigma / span);
    }
    return true;
  }
};

}  // namespace

bool RefinePlacement(const SurveyInput& in, const std::vector<int>& frames, const std::vector<Eigen::Matrix3d>& R,
                     const std::vector<Use>& uses, const std::vector<double>& fixed_h,
                     const std::vector<Eigen::Vector3d>& dv, const SurveyConfig& config,
                     std::vector<Eigen::Vector3d>* cameras, std::vector<Eigen::Vector3d>* bases,
                     std::vector<double>* heights) {
  const int K = static_cast<int>(frames.size());
  std::vector<Eigen::Vector3d> p = *cameras, b = *bases;
  std::vector<double> h = *heights;
  ceres::Problem problem;
  const rig_model::CameraModel& cam = in.camera;
  for (size_t t = 0; t < uses.size(); ++t) {
    for (const auto& [k, s] : uses[t].sightings) {
      const ConeSighting& c = in.frames[frames[k]].cones[s];
      for (const bool peak : {true, false}) {
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<RayCost, 2, 3, 3, 1>(
                                     new RayCost{R[k].transpose(), peak ? c.peak_px : c.base_px, cam.fx_px, cam.fy_px,
                                                 cam.cx_px, cam.cy_px, 1.0 / config.sigma_px, peak}),
                                 new ceres::CauchyLoss(config.robust_px / config.sigma_px), p[k].data(), b[t].data(),
                                 &h[t]);
      }
    }
    if (!std::isnan(fixed_h[t]) && problem.HasParameterBlock(&h[t])) problem.SetParameterBlockConstant(&h[t]);
  }
  // The accelerometer, up to the solution's scale (units per metre), whose start is the least-squares
  // fit of the linear solution's second differences to dv.
  double scale = 1.0, num = 0.0, den = 0.0;
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();
  std::vector<std::array<double, 3>> w;  // (wa, wc, span) per k, span 0 where no row
  w.assign(K, {0.0, 0.0, 0.0});
  for (int k = 1; k + 1 < K; ++k) {
    const double ta = in.frames[frames[k - 1]].stamp_s, tb = in.frames[frames[k]].stamp_s,
                 tc = in.frames[frames[k + 1]].stamp_s;
    if (tc - ta > 0.5 || !dv[k].allFinite()) continue;
    w[k] = {1.0 / (tb - ta), 1.0 / (tc - tb), 0.5 * (tc - ta)};
    const Eigen::Vector3d d = w[k][1] * (p[k + 1] - p[k]) - w[k][0] * (p[k] - p[k - 1]);
    num += d.dot(dv[k]), den += dv[k].squaredNorm();
  }
  if (den > 0.0 && num > 0.0) scale = num / den;
  for (int k = 1; k + 1 < K; ++k) {
    if (w[k][2] == 0.0) continue;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<AccelCost, 3, 3, 3, 3, 1, 3>(
                                 new AccelCost{dv[k], w[k][0], w[k][1], w[k][2], 1.0 / config.accel_noise_m_s2}),
                             nullptr, p[k - 1].data(), p[k].data(), p[k + 1].data(), &scale, bias.data());
  }
  if (problem.HasParameterBlock(&scale)) problem.SetParameterLowerBound(&scale, 0, 1e-3);
  if (problem.HasParameterBlock(p[0].data())) problem.SetParameterBlockConstant(p[0].data());
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_SCHUR;
  options.max_num_iterations = 50;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable()) return false;
  *cameras = p, *bases = b, *heights = h;
  return true;
}

}  // namespace cone_survey
