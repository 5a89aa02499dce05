// Speed of linear initialisation + refinement on the nine cone points against
// OpenCV's solvePnP on the same inputs, in the same process. Prints
// `BENCH cone_tracker.<name> <value> <unit>` lines and the ratio to SQPNP.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>

#include "opencv_baseline.h"
#include "synthetic.h"

namespace {

struct Input {
  cone_tracker::sim::Case truth;
  std::vector<Eigen::Vector2d> noisy;
};
using Solver = std::function<bool(const Input&)>;

// All solvers run case by case, interleaved, so that load from other
// processes hits them alike. Returns, per solver, the median over cases of the
// per-call time (µs, mean of `repeats` calls), and counts failed cases.
std::vector<double> MedianMicros(const std::vector<Input>& inputs, int repeats, const std::vector<Solver>& solvers,
                                 std::vector<int>* failures) {
  std::vector<std::vector<double>> times(solvers.size());
  failures->assign(solvers.size(), 0);
  for (const Input& in : inputs) {
    for (size_t s = 0; s < solvers.size(); ++s) {
      bool ok = true;
      const auto start = std::chrono::steady_clock::now();
      for (int r = 0; r < repeats; ++r) ok = solvers[s](in) && ok;
      const auto elapsed = std::chrono::steady_clock::now() - start;
      times[s].push_back(std::chrono::duration<double, std::micro>(elapsed).count() / repeats);
      (*failures)[s] += ok ? 0 : 1;
    }
  }
  std::vector<double> medians;
  for (std::vector<double>& t : times) {
    std::nth_element(t.begin(), t.begin() + t.size() / 2, t.end());
    medians.push_back(t[t.size() / 2]);
  }
  return medians;
}

void Print(const std::string& name, double value, const char* unit) {
  std::printf("BENCH cone_tracker.%s %.4g %s\n", name.c_str(), value, unit);
}

Solver Ours(cone_tracker::PnpMethod method, bool covariance) {
  cone_tracker::PnpOptions o;
  o.method = method;
  o.compute_covariance = covariance;
  return [o](const Input& in) { return cone_tracker::SolvePnp(in.truth.camera, in.truth.model, in.noisy, o).ok; };
}

}  // namespace

int main() {
  using cone_tracker::PnpMethod;
  std::mt19937 rng(2024);
  std::vector<Input> inputs;
  for (int k = 0; k < 2000; ++k) {
    Input in{cone_tracker::sim::ConeLayout(rng), {}};
    in.noisy = cone_tracker::sim::AddNoise(rng, in.truth.image, 1.0);
    inputs.push_back(in);
  }
  constexpr int kRepeats = 5;
  std::printf("cone layout, 9 points, sigma 1 px, %zu cases, median over cases of the mean of %d calls\n",
              inputs.size(), kRepeats);
  std::vector<std::string> names = {"best", "best_with_covariance", "simplex_is", "oia", "epnp_gn", "ceres"};
  std::vector<Solver> solvers = {Ours(PnpMethod::kBest, false),      Ours(PnpMethod::kBest, true),
                                 Ours(PnpMethod::kSimplexIs, false), Ours(PnpMethod::kOia, false),
                                 Ours(PnpMethod::kEpnpGn, false),    Ours(PnpMethod::kCeres, false)};
  for (const auto& m : cone_tracker::baseline::OpenCvMethods()) {
    std::string name = m.name;
    std::replace(name.begin(), name.end(), '-', '_');
    names.push_back(name);
    const int flag = m.flag;
    solvers.push_back([flag](const Input& in) {
      pose_math::Pose T;
      return cone_tracker::baseline::SolveOpenCv(flag, in.truth.camera, in.truth.model, in.noisy, &T);
    });
  }
  std::vector<int> failures;
  const std::vector<double> medians = MedianMicros(inputs, kRepeats, solvers, &failures);
  double best_us = 0.0, sqpnp_us = 0.0;
  for (size_t s = 0; s < names.size(); ++s) {
    Print(names[s] + "_median", medians[s], "us");
    if (failures[s] > 0) Print(names[s] + "_failed_cases", failures[s], "cases");
    if (names[s] == "best") best_us = medians[s];
    if (names[s] == "cv_sqpnp") sqpnp_us = medians[s];
  }
  Print("best_over_sqpnp", best_us / sqpnp_us, "ratio");
  return 0;
}
