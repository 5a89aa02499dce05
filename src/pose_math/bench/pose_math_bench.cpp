// Speed of pose_math's conversions against Eigen's own, on the same inputs in
// the same process. Prints "BENCH pose_math.<name> <value> <unit>" lines.
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <random>
#include <vector>

#include "pose_math/covariance.h"
#include "pose_math/rotation.h"

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kInputs = 4096;
constexpr int kRepeats = 31;

// Median over kRepeats passes of the time per call, in ns. `sink` keeps the
// optimiser from dropping the work.
double MedianNsPerCall(const std::function<double(int)>& call) {
  std::vector<double> per_call;
  volatile double sink = 0.0;
  for (int r = 0; r < kRepeats; ++r) {
    const auto t0 = Clock::now();
    double acc = 0.0;
    for (int i = 0; i < kInputs; ++i) acc += call(i);
    const auto t1 = Clock::now();
    sink = sink + acc;
    per_call.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / kInputs);
  }
  std::nth_element(per_call.begin(), per_call.begin() + kRepeats / 2, per_call.end());
  return per_call[kRepeats / 2];
}

void Report(const char* name, double ours_ns, double baseline_ns, const char* baseline) {
  std::printf("%-28s ours %8.1f ns   %s %8.1f ns   ratio %.2f\n", name, ours_ns, baseline, baseline_ns,
              ours_ns / baseline_ns);
  std::printf("BENCH pose_math.%s %.1f ns\n", name, ours_ns);
  std::printf("BENCH pose_math.%s_baseline %.1f ns\n", name, baseline_ns);
  std::printf("BENCH pose_math.%s_ratio %.2f x\n", name, ours_ns / baseline_ns);
}

}  // namespace

int main() {
  std::mt19937 rng(7);
  std::normal_distribution<double> n01;
  std::vector<pose_math::Quat> qs(kInputs);
  std::vector<Eigen::Quaterniond> eqs(kInputs);
  std::vector<Eigen::Matrix3d> Rs(kInputs);
  std::vector<pose_math::Matrix6d> cov6s(kInputs);
  for (int i = 0; i < kInputs; ++i) {
    qs[i] = pose_math::Quat(n01(rng), n01(rng), n01(rng), n01(rng)).normalized();
    eqs[i] = pose_math::EigenFromThesis(qs[i]);
    Rs[i] = pose_math::RotationFromQuat(qs[i]);
    Eigen::Matrix<double, 6, 6> G;
    for (int k = 0; k < 36; ++k) G.data()[k] = n01(rng);
    cov6s[i] = G * G.transpose();
  }

  std::printf("pose_math vs Eigen, median of %d passes over %d inputs\n", kRepeats, kInputs);
  Report("quat_from_rotation", MedianNsPerCall([&](int i) { return pose_math::QuatFromRotation(Rs[i])[1]; }),
         MedianNsPerCall([&](int i) { return Eigen::Quaterniond(Rs[i]).x(); }), "Eigen::Quaterniond(R)");
  Report("rotation_from_quat", MedianNsPerCall([&](int i) { return pose_math::RotationFromQuat(qs[i])(0, 1); }),
         MedianNsPerCall([&](int i) { return eqs[i].toRotationMatrix()(0, 1); }), "Eigen toRotationMatrix");
  Report("angle_axis_from_rotation",
         MedianNsPerCall([&](int i) { return pose_math::AngleAxisFromRotation(Rs[i]).angle_rad; }),
         MedianNsPerCall([&](int i) { return Eigen::AngleAxisd(Rs[i]).angle(); }), "Eigen::AngleAxisd(R)");
  // The covariance round trip has no library equivalent; its baseline is the
  // plain dense J Σ Jᵀ product it reduces to, with J built by Eigen.
  Report("cov_ros_thesis_round_trip", MedianNsPerCall([&](int i) {
           return pose_math::CovarianceRosFromThesis(qs[i], pose_math::CovarianceThesisFromRos(qs[i], cov6s[i]))(0, 0);
         }),
         MedianNsPerCall([&](int i) {
           Eigen::Matrix<double, 7, 6> J = Eigen::Matrix<double, 7, 6>::Zero();
           J.topRightCorner<4, 3>() = 0.5 * pose_math::RightMatrix(qs[i]).rightCols<3>();
           J.bottomLeftCorner<3, 3>().setIdentity();
           const Eigen::Matrix<double, 7, 7> c7 = J * cov6s[i] * J.transpose();
           Eigen::Matrix<double, 6, 7> Jp = 4.0 * J.transpose();
           Jp.topRows<3>() = J.transpose().topRows<3>();
           return (Jp * c7 * Jp.transpose())(0, 0);
         }),
         "dense J*S*J'");
  return 0;
}
