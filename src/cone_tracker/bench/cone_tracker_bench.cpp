// Speed of linear initialisation + refinement on the nine cone points against
// OpenCV's solvePnP on the same inputs, in the same process. Prints
// `BENCH cone_tracker.<name> <value> <unit>` lines and the ratio.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>

#include "opencv_baseline.h"
#include "synthetic.h"

namespace {

using cone_tracker::sim::Case;

struct Input {
  Case truth;
  std::vector<Eigen::Vector2d> noisy;
};

// Median over cases of the per-call time (µs), each case timed over `repeats` calls.
double MedianMicros(const std::vector<Input>& inputs, int repeats, const std::function<bool(const Input&)>& solve,
                    int* failures) {
  std::vector<double> times;
  *failures = 0;
  for (const Input& in : inputs) {
    bool ok = true;
    const auto start = std::chrono::steady_clock::now();
    for (int r = 0; r < repeats; ++r) ok = solve(in) && ok;
    times.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count() /
                    repeats);
    *failures += ok ? 0 : 1;
  }
  std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
  return times[times.size() / 2];
}

void Print(const char* name, double value, const char* unit) {
  std::printf("BENCH cone_tracker.%s %.4g %s\n", name, value, unit);
}

}  // namespace

int main() {
  std::mt19937 rng(2024);
  std::vector<Input> inputs;
  for (int k = 0; k < 2000; ++k) {
    Input in{cone_tracker::sim::ConeLayout(rng), {}};
    in.noisy = cone_tracker::sim::AddNoise(rng, in.truth.image, 1.0);
    inputs.push_back(in);
  }
  constexpr int kRepeats = 5;
  int failures = 0;
  std::printf("cone layout, 9 points, sigma 1 px, %zu cases, median of per-case mean over %d calls\n", inputs.size(),
              kRepeats);

  const auto ours = [&](cone_tracker::PnpMethod method, bool covariance) {
    cone_tracker::PnpOptions o;
    o.method = method;
    o.compute_covariance = covariance;
    return [o](const Input& in) { return cone_tracker::SolvePnp(in.truth.camera, in.truth.model, in.noisy, o).ok; };
  };
  const double best_us = MedianMicros(inputs, kRepeats, ours(cone_tracker::PnpMethod::kBest, false), &failures);
  Print("best_median", best_us, "us");
  Print("best_failures", failures, "cases");
  const double best_cov_us = MedianMicros(inputs, kRepeats, ours(cone_tracker::PnpMethod::kBest, true), &failures);
  Print("best_with_covariance_median", best_cov_us, "us");
  for (const auto m :
       {cone_tracker::PnpMethod::kSimplexIs, cone_tracker::PnpMethod::kOia, cone_tracker::PnpMethod::kEpnpGn}) {
    const std::string name = cone_tracker::PnpMethodName(m) + "_median";
    Print(name.c_str(), MedianMicros(inputs, kRepeats, ours(m, false), &failures), "us");
  }
  double sqpnp_us = 0.0;
  for (const auto& m : cone_tracker::baseline::OpenCvMethods()) {
    const double us = MedianMicros(
        inputs, kRepeats,
        [&](const Input& in) {
          pose_math::Pose T;
          return cone_tracker::baseline::SolveOpenCv(m.flag, in.truth.camera, in.truth.model, in.noisy, &T);
        },
        &failures);
    std::string name = m.name;
    std::replace(name.begin(), name.end(), '-', '_');
    Print((name + "_median").c_str(), us, "us");
    if (m.name == std::string("cv-sqpnp")) sqpnp_us = us;
  }
  Print("best_over_sqpnp", best_us / sqpnp_us, "ratio");
  return 0;
}
