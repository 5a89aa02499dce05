// OpenCV's solvePnP as the baseline for the benchmark and the experiments.
#pragma once
#include <string>
#include <vector>

#include "cone_tracker/pose/pnp.h"

namespace cone_tracker {
namespace baseline {

struct OpenCvMethod {
  int flag;          // cv::SOLVEPNP_*
  const char* name;  // "cv-iterative", ...
};
const std::vector<OpenCvMethod>& OpenCvMethods();  // ITERATIVE, EPNP, SQPNP
// False if OpenCV reports failure (or throws).
bool SolveOpenCv(int flag, const CameraModel& camera, const std::vector<Eigen::Vector3d>& model,
                 const std::vector<Eigen::Vector2d>& image, pose_math::Pose* T_camera_model);

}  // namespace baseline
}  // namespace cone_tracker
