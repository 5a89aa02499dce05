// The survey's first estimate: tracks placed by linear structure-from-motion with known rotations,
// grouped into cones, matched to the inventory by height. ROS-free.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "cone_survey/survey.h"
#include "imu_track.h"

namespace cone_survey {

// One sighting used by the adjustment: adjusted frame k saw inventory cone `cone` at these pixels.
struct Observation {
  int frame = 0;  // index into the adjusted frames
  int cone = 0;   // inventory index
  ConeSighting px;
};

struct InitialSurvey {
  std::vector<int> frames;                      // adjusted frames: indices into SurveyInput::frames
  std::vector<Eigen::Matrix3d> R_world_camera;  // per adjusted frame, z up
  std::vector<Eigen::Vector3d> p_camera_m;      // per adjusted frame
  std::vector<Eigen::Vector3d> base_m;          // per inventory cone
  std::vector<Observation> observations;
};

// Places the tracks (heights up to one scale), groups tracks of one cone, fixes the scale from the
// inventory's heights and assigns every group an inventory cone. False with a message naming the
// inventory entries not seen and the found cones the inventory lacks.
bool InitialiseSurvey(const SurveyInput& input, const Inventory& inventory, const SurveyConfig& config,
                      const GyroIntegrator& gyro, const Eigen::Vector3d& bias_imu, const std::vector<Track>& tracks,
                      InitialSurvey* out, std::string* error);

}  // namespace cone_survey
