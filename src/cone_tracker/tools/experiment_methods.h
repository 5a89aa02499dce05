// The algorithm combinations of chapter 7.1 (figures 7.1, 7.2) plus our
// "best", full Ceres and OpenCV's solvePnP baselines, all run on one trial.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "cone_tracker/pose/algorithms.h"
#include "synthetic.h"

namespace cone_tracker {
namespace experiments {

struct Trial {
  sim::Case truth;
  std::vector<Eigen::Vector2d> noisy_px;
  Correspondences c;      // from noisy_px
  double sigma_px = 1.0;  // the noise added, told to SolvePnp as a user would
};
Trial MakeTrial(sim::Case truth, std::vector<Eigen::Vector2d> noisy_px, double sigma_px);

struct Method {
  std::string name;  // label in plots and CSV
  std::function<bool(const Trial&, pose_math::Pose*)> solve;
};
// Groups 1–5 of figures 7.1 and 7.2 (1-based), each followed by the common
// comparison methods (ours: best, ceres; OpenCV: iterative, epnp, sqpnp).
std::vector<Method> GroupMethods(int group);
// The cone layout: the refinements the tracker could use plus the baselines.
std::vector<Method> ConeMethods();

}  // namespace experiments
}  // namespace cone_tracker
