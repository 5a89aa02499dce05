// The survey's bundle adjustment (Ceres): cone bases, camera poses and the gyro bias from the cones'
// peak and base pixels, the gyro's relative rotations and the accelerometer's up direction, in the
// inventory's frame (origin cone fixed, +x cone on the x axis). ROS-free.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "initialise.h"

namespace cone_survey {

struct BundleResult {
  std::vector<Eigen::Vector3d> sigma_m;    // per inventory cone (zero where the frame fixes it)
  std::vector<double> correlation_factor;  // per cone: its covariance over the independent-error one
  double scale_sigma = 0.0;                // the layout's scale's 1-sigma (fraction) from the detector's per-cone bias
  std::vector<double> error_px;            // per observation: the larger of its peak and base errors
  double rms_px = 0.0;                     // per coordinate over all observations
  Eigen::Vector3d bias_imu = Eigen::Vector3d::Zero();
  double base_offset_px = 0.0;  // the detected bases' offset below the model's, along the cone's image axis
};

// Refines `survey` in place. False with a message when the solver or the covariance fails.
bool AdjustSurvey(const SurveyInput& input, const Inventory& inventory, const SurveyConfig& config,
                  const GyroIntegrator& gyro, const Eigen::Vector3d& bias_imu, InitialSurvey* survey,
                  BundleResult* result, std::string* error);

}  // namespace cone_survey
