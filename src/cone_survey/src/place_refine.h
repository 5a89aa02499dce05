// The linear placement's tracks refined by their pixel errors (rotations known), with the
// accelerometer holding the scale along the walk. ROS-free.
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cone_survey/survey.h"

namespace cone_survey {

struct Use {  // a track's sightings in the adjusted frames
  int track;
  std::vector<std::pair<int, int>> sightings;  // (adjusted frame, sighting)
};

// Refines cameras (the first stays at the origin), bases and the free heights (NaN in fixed_h) by the
// peak and base pixel errors (Cauchy loss at config.robust_px) and the accelerometer's velocity
// changes dv (per frame, m/s, NaN where none) up to one scale and one constant acceleration error.
// The linear solve's rows are distances, which every unknown can shrink by moving toward the first
// camera, so a stretch of the walk that few tracks link to the fixed height came out small; pixel
// errors do not change with the scale. False when Ceres fails (the inputs are left as they were).
bool RefinePlacement(const SurveyInput& in, const std::vector<int>& frames, const std::vector<Eigen::Matrix3d>& R,
                     const std::vector<Use>& uses, const std::vector<double>& fixed_h,
                     const std::vector<Eigen::Vector3d>& dv, const SurveyConfig& config,
                     std::vector<Eigen::Vector3d>* cameras, std::vector<Eigen::Vector3d>* bases,
                     std::vector<double>* heights);

}  // namespace cone_survey
