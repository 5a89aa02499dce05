#include <cmath>

#include "pose_ekf/testing/synthetic_rig.h"
#include "pose_math/covariance.h"

#include <boost/math/distributions/chi_squared.hpp>

namespace pose_ekf_test {
namespace {

struct Accumulator {
  RunStats s;
  double sum_rot2 = 0.0, sum_pos2 = 0.0, sum_nees = 0.0;
  int within = 0;
  void Add(const Truth& truth, const pose_math::PoseWithCovariance& est, bool with_cov) {
    const Eigen::Matrix<double, 6, 1> e = PoseError(truth.T_cones_camera, est.pose);
    sum_rot2 += e.tail<3>().squaredNorm();
    sum_pos2 += e.head<3>().squaredNorm();
    s.max_rotation_rad = std::max(s.max_rotation_rad, e.tail<3>().norm());
    if (with_cov) {
      const pose_math::Matrix6d cov6 = pose_math::CovarianceRosFromThesis(est.pose.q, est.cov);
      for (int i = 0; i < 6; ++i) within += std::abs(e[i]) <= 3.0 * std::sqrt(cov6(i, i));
      const double nees = e.dot(cov6.ldlt().solve(e));
      s.nees.push_back(nees);
      sum_nees += nees;
    }
    ++s.samples;
  }
  RunStats Finish() {
    if (s.samples > 0) {
      s.rms_rotation_rad = std::sqrt(sum_rot2 / s.samples);
      s.rms_position_m = std::sqrt(sum_pos2 / s.samples);
      s.fraction_within_3_sigma = within / (6.0 * s.samples);
      s.mean_nees = sum_nees / s.samples;
    }
    return s;
  }
};

}  // namespace

RunStats RunFilter(const pose_ekf::EkfConfig& config, const std::vector<Event>& events, double warmup_s,
                   const std::function<bool(double)>& in_window) {
  pose_ekf::MeasurementBuffer buffer(config);
  Accumulator acc;
  for (const Event& e : events) {
    if (e.is_camera) {
      buffer.AddCamera(e.camera);
      continue;
    }
    buffer.AddImu(e.imu);
    if (!buffer.filter().initialized() || e.stamp_s < warmup_s) continue;
    if (in_window && !in_window(e.stamp_s)) continue;
    acc.Add(e.truth, buffer.filter().Pose(), true);
  }
  acc.s.camera_gated = buffer.counters().camera_gated;
  acc.s.reinits = buffer.counters().reinits;
  return acc.Finish();
}

double ChiSquareQuantile(double k, double p) { return boost::math::quantile(boost::math::chi_squared(k), p); }

RunStats CameraOnlyStats(const std::vector<Event>& events) {
  Accumulator acc;
  for (const Event& e : events) {
    if (!e.is_camera) continue;
    pose_math::PoseWithCovariance est;
    est.pose = e.camera.T_cones_camera;
    acc.Add(e.truth, est, false);
  }
  return acc.Finish();
}

}  // namespace pose_ekf_test
