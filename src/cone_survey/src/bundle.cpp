#include "bundle.h"

#include <cmath>
#include <map>
#include <memory>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <Eigen/Geometry>

#include "rig_model/layout.h"

namespace cone_survey {
namespace {

constexpr double kDeg = M_PI / 180.0;

// Pixel errors of a cone's peak and base in one frame: the model points corrected for the eye
// (3.16) (3.17) (3.18), through the pinhole of the undistorted pixels (3.10 without distortion).
// The detected base lies off the model's base point along the cone's image axis by `base_px`
// (positive: below it), one unknown for the walk: an offset of the detector's base reads as cones of
// another size, which scales the whole layout.
struct Reprojection {
  ConeSighting seen;
  double height_m, tau, fx, fy, cx, cy;
  bool Errors(const double* q_world_camera, const double* p_camera, const double* base, const double* base_px,
              double* r, double* length_error = nullptr) const {
    const Eigen::Map<const Eigen::Quaterniond> q(q_world_camera);
    const Eigen::Map<const Eigen::Vector3d> p(p_camera), b(base);
    const auto points = rig_model::CorrectedModelPoints(b, height_m, tau, p);
    Eigen::Vector2d px[2];
    const int index[2] = {0, 2};  // peak, base of (peak, mid, base)
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector3d c = q.conjugate() * (points[index[i]] - p);
      if (!(c.z() > 1e-3)) return false;
      px[i] = Eigen::Vector2d(fx * c.x() / c.z() + cx, fy * c.y() / c.z() + cy);
    }
    const Eigen::Vector2d foot = px[1] - *base_px * (px[0] - px[1]).normalized();
    r[0] = px[0].x() - seen.peak_px.x(), r[1] = px[0].y() - seen.peak_px.y();
    r[2] = foot.x() - seen.base_px.x(), r[3] = foot.y() - seen.base_px.y();
    if (length_error) {  // how much longer the detected cone is than the model's, as a fraction
      const Eigen::Vector2d axis = px[0] - foot;
      *length_error = ((seen.peak_px - seen.base_px) - axis).dot(axis) / axis.squaredNorm();
    }
    return true;
  }
};

struct ReprojectionCost {
  Reprojection model;
  double inv_sigma;
  bool operator()(const double* q, const double* p, const double* b, const double* offset, double* r) const {
    if (!model.Errors(q, p, b, offset, r)) return false;
    for (int i = 0; i < 4; ++i) r[i] *= inv_sigma;
    return true;
  }
};

// The gyro's rotation between two adjusted frames, measured with bias0 and corrected to first
// order for the estimated bias: R_a^T R_b = dR(bias0) Exp(-R_ci (b - bias0) dt).
struct GyroCost {
  Eigen::Quaterniond dq;
  Eigen::Matrix3d R_camera_imu;
  Eigen::Vector3d bias0;
  double dt_s, inv_sigma;
  template <typename T>
  bool operator()(const T* qa, const T* qb, const T* bias, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> Qa(qa), Qb(qb);
    const Eigen::Matrix<T, 3, 1> b(bias[0] - T(bias0.x()), bias[1] - T(bias0.y()), bias[2] - T(bias0.z()));
    const Eigen::Matrix<T, 3, 1> w = R_camera_imu.cast<T>() * b * T(-dt_s);
    T aa[3] = {w[0], w[1], w[2]}, wxyz[4];
    ceres::AngleAxisToQuaternion(aa, wxyz);
    const Eigen::Quaternion<T> corr(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);
    const Eigen::Quaternion<T> err = (dq.cast<T>() * corr).conjugate() * (Qa.conjugate() * Qb);
    const T sign = err.w() < T(0) ? T(-1) : T(1);
    for (int i = 0; i < 3; ++i) r[i] = T(2.0 * inv_sigma) * sign * err.vec()[i];
    return true;
  }
};

// The accelerometer's up direction, in the world: +z.
struct GravityCost {
  Eigen::Vector3d up_camera;
  double inv_sigma;
  template <typename T>
  bool operator()(const T* q, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> Q(q);
    const Eigen::Matrix<T, 3, 1> up = Q * up_camera.cast<T>();
    r[0] = up[0] * T(inv_sigma), r[1] = up[1] * T(inv_sigma), r[2] = (up[2] - T(1)) * T(inv_sigma);
    return true;
  }
};

struct BiasPrior {
  Eigen::Vector3d bias0;
  double inv_sigma;
  template <typename T>
  bool operator()(const T* b, T* r) const {
    for (int i = 0; i < 3; ++i) r[i] = (b[i] - T(bias0[i])) * T(inv_sigma);
    return true;
  }
};

// How many times fewer independent sightings a cone has than sightings: the detector's errors of
// one cone are correlated from frame to frame (the tip a few pixels wide, the front arc of the base
// change little between frames), so its position is known from about n / f independent ones, and
// its covariance is f times the adjustment's, which assumes independent errors. f is the integrated
// autocorrelation of its pixel errors over the adjusted frames, 1 + 2 sum_l rho_l, summed up to
// the first lag whose correlation is not positive (Sokal's window, at most 5 s at 10 Hz);
// rho_l pools the four coordinates over the pairs of its sightings l frames apart.
double CorrelationFactor(const std::map<int, Eigen::Vector4d>& errors) {
  if (errors.size() < 4) return 1.0;
  Eigen::Vector4d mean = Eigen::Vector4d::Zero();
  for (const auto& [k, r] : errors) mean += r;
  mean /= static_cast<double>(errors.size());
  double var = 0.0;
  for (const auto& [k, r] : errors) var += (r - mean).squaredNorm();
  var /= static_cast<double>(errors.size());
  if (!(var > 0.0)) return 1.0;
  double f = 1.0;
  for (int lag = 1; lag <= 50; ++lag) {
    double sum = 0.0;
    int pairs = 0;
    for (const auto& [k, r] : errors) {
      const auto other = errors.find(k + lag);
      if (other == errors.end()) continue;
      sum += (r - mean).dot(other->second - mean);
      ++pairs;
    }
    if (pairs < 3) break;
    const double rho = sum / pairs / var;
    if (!(rho > 0.0)) break;
    f += 2.0 * rho;
  }
  return f;
}

}  // namespace

bool AdjustSurvey(const SurveyInput& in, const Inventory& inv, const SurveyConfig& config, const GyroIntegrator& gyro,
                  const Eigen::Vector3d& bias0, InitialSurvey* s, BundleResult* result, std::string* error) {
  const int K = static_cast<int>(s->frames.size());
  std::vector<Eigen::Vector4d> q(K);  // Eigen's storage order x, y, z, w
  for (int k = 0; k < K; ++k) q[k] = Eigen::Quaterniond(s->R_world_camera[k]).normalized().coeffs();
  Eigen::Vector3d bias = bias0;
  double base_offset_px = 0.0;
  ceres::Problem problem;
  const rig_model::CameraModel& cam = in.camera;
  std::vector<ReprojectionCost> models;
  for (const Observation& o : s->observations) {
    const rig_model::ConeSpec& c = inv.cones[o.cone];
    const ReprojectionCost cost{{o.px, c.height_m, c.tau, cam.fx_px, cam.fy_px, cam.cx_px, cam.cy_px},
                                1.0 / config.sigma_px};
    models.push_back(cost);
    problem.AddResidualBlock(
        new ceres::NumericDiffCostFunction<ReprojectionCost, ceres::CENTRAL, 4, 4, 3, 3, 1>(new ReprojectionCost(cost)),
        new ceres::CauchyLoss(config.robust_px / config.sigma_px), q[o.frame].data(), s->p_camera_m[o.frame].data(),
        s->base_m[o.cone].data(), &base_offset_px);
  }
  for (int k = 0; k < K; ++k) {
    Eigen::Vector3d up;
    if (gyro.UpInCamera(in.frames[s->frames[k]].stamp_s, 0.05, &up))
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<GravityCost, 3, 4>(
                                   new GravityCost{up, 1.0 / (config.gravity_sigma_deg * kDeg)}),
                               nullptr, q[k].data());
  }
  for (int k = 0; k + 1 < K; ++k) {
    const double ta = in.frames[s->frames[k]].stamp_s, tb = in.frames[s->frames[k + 1]].stamp_s;
    const double dt = tb - ta;
    const double sigma = config.gyro_noise_rad_s * std::sqrt(dt) + 0.05 * kDeg;
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<GyroCost, 3, 4, 4, 3>(
            new GyroCost{Eigen::Quaterniond(gyro.Delta(ta, tb, bias0)), in.R_camera_imu, bias0, dt, 1.0 / sigma}),
        nullptr, q[k].data(), q[k + 1].data(), bias.data());
  }
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<BiasPrior, 3, 3>(new BiasPrior{bias0, 1.0 / 0.01}), nullptr,
                           bias.data());
  for (int k = 0; k < K; ++k) problem.SetManifold(q[k].data(), new ceres::EigenQuaternionManifold);
  problem.SetParameterBlockConstant(s->base_m[inv.origin].data());
  problem.SetManifold(s->base_m[inv.x_axis].data(), new ceres::SubsetManifold(3, {1}));

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_SCHUR;
  options.max_num_iterations = 100;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable()) {
    *error = "the bundle adjustment failed: " + summary.message;
    return false;
  }
  for (int k = 0; k < K; ++k) s->R_world_camera[k] = Eigen::Quaterniond(q[k]).normalized().toRotationMatrix();
  result->bias_imu = bias;
  result->base_offset_px = base_offset_px;
  // Errors per observation, in pixels.
  double sum_sq = 0.0;
  result->error_px.assign(models.size(), 1e9);
  std::vector<std::map<int, Eigen::Vector4d>> series(inv.cones.size());  // per cone: adjusted frame -> errors
  std::vector<double> length_sum(inv.cones.size(), 0.0);
  std::vector<int> length_n(inv.cones.size(), 0);
  for (size_t i = 0; i < models.size(); ++i) {
    const Observation& o = s->observations[i];
    double r[4], length_error = 0.0;
    if (!models[i].model.Errors(q[o.frame].data(), s->p_camera_m[o.frame].data(), s->base_m[o.cone].data(),
                                &base_offset_px, r, &length_error))
      continue;
    result->error_px[i] = std::max(std::hypot(r[0], r[1]), std::hypot(r[2], r[3]));
    sum_sq += r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3];
    if (result->error_px[i] < config.outlier_px) {
      series[o.cone][o.frame] = Eigen::Map<Eigen::Vector4d>(r);
      length_sum[o.cone] += length_error;
      ++length_n[o.cone];
    }
  }
  // The detector's bias on each cone's length in the image (the tip, the base's front arc), as a
  // fraction of its length: a random bias per cone, eps_i, which the walk's sightings average but
  // cannot remove. The known heights give the scale, so it comes out off by the mean of the eps_i,
  // whose sigma is sd(eps) / sqrt(cones) (the spread of the per-cone means over the cones measures
  // sd(eps); the common part of the eps_i is that scale error and leaves no trace).
  std::vector<double> eps;
  for (size_t i = 0; i < inv.cones.size(); ++i)
    if (length_n[i] > 0) eps.push_back(length_sum[i] / length_n[i]);
  double eps_mean = 0.0, eps_var = 0.0;
  for (double e : eps) eps_mean += e / eps.size();
  for (double e : eps) eps_var += (e - eps_mean) * (e - eps_mean) / std::max<size_t>(1, eps.size() - 1);
  result->scale_sigma = eps.size() > 1 ? std::sqrt(eps_var / eps.size()) : 0.0;
  result->rms_px = models.empty() ? 0.0 : std::sqrt(sum_sq / (4.0 * models.size()));
  // Each cone's covariance in the inventory's frame, scaled by the fit's variance factor.
  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::SPARSE_QR;
  cov_options.apply_loss_function = true;
  ceres::Covariance covariance(cov_options);
  std::vector<std::pair<const double*, const double*>> blocks;
  for (size_t i = 0; i < inv.cones.size(); ++i)
    if (static_cast<int>(i) != inv.origin) blocks.emplace_back(s->base_m[i].data(), s->base_m[i].data());
  if (!covariance.Compute(blocks, &problem)) {
    *error = "the bundle adjustment's covariance is singular: the walk does not fix every cone";
    return false;
  }
  const double dof = std::max(1, summary.num_residuals_reduced - summary.num_effective_parameters_reduced);
  const double variance_factor = 2.0 * summary.final_cost / dof;
  result->sigma_m.assign(inv.cones.size(), Eigen::Vector3d::Zero());
  result->correlation_factor.assign(inv.cones.size(), 1.0);
  for (size_t i = 0; i < inv.cones.size(); ++i) {
    result->correlation_factor[i] = CorrelationFactor(series[i]);
    if (static_cast<int>(i) == inv.origin) continue;
    Eigen::Matrix3d C;
    covariance.GetCovarianceBlock(s->base_m[i].data(), s->base_m[i].data(), C.data());
    // The scale's error moves every cone along its position from the origin cone.
    const Eigen::Vector3d& p = s->base_m[i];
    const Eigen::Matrix3d total = variance_factor * result->correlation_factor[i] * C +
                                  result->scale_sigma * result->scale_sigma * p * p.transpose();
    result->sigma_m[i] = total.diagonal().cwiseMax(0.0).cwiseSqrt();
  }
  return true;
}

}  // namespace cone_survey
